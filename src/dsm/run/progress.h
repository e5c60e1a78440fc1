// SPDX-License-Identifier: MIT
// Progress of a run on the console. On a terminal one line is redrawn in place (at most five times a
// second): frame i/N, frames per second, real-time factor, keyframes, points, tracking state, time
// left. When the output is not a terminal (a log file, a pipe) the same text is printed as a plain
// line every `interval_s` seconds. Events (tracking lost, regained, a new map) are printed as lines
// of their own above it.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace dsm {

struct ProgressState {
  int frame = 0;        // Input index of the frame just processed.
  int done = 0;         // Frames taken so far (processed or skipped) ...
  int total = 0;        // ... of this many.
  double elapsed_s = 0.0;
  double recording_s = 0.0;  // Time span of the frames taken (0: unknown).
  int keyframes = 0, points = 0;
  std::string state;  // "initialising" | "tracking" | "lost".
};

// "frame 120/600 (20%)  45.1 fps  2.25x real time  34 keyframes  8123 points  tracking  0:11 left"
std::string FormatProgress(const ProgressState& s);

class Progress {
 public:
  // `out` null: prints nothing.
  Progress(std::FILE* out, bool terminal, double interval_s);
  // Shows `s` if the last was shown long enough ago (or `force`).
  void Update(const ProgressState& s, bool force = false);
  // A line of its own, to `to` (default: the progress output; e.g. stderr for warnings).
  void Event(const std::string& line, std::FILE* to = nullptr);
  // Clears the terminal line, so that what follows starts on a clean line.
  void Finish();

 private:
  void Clear();
  std::FILE* out_;
  bool terminal_;
  double interval_s_;
  bool shown_ = false;  // The terminal line holds a progress text.
  std::chrono::steady_clock::time_point last_;
  std::string text_;  // The last progress text.
};

}  // namespace dsm
