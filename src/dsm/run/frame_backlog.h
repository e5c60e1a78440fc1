// SPDX-License-Identifier: MIT
// The realtime pace's frames that wait for the mapping side (run.cc).
//
// A frame tracked while the mapping side is still busy with the keyframe before it (its mapping,
// or the young map's or a loop adjustment after its publication: up to a second) is aligned with a
// keyframe the sequential run would already have moved or replaced; the frames after it, the
// keyframes made from them and the adjustment, taken up in parts between those keyframes, all go
// their own way from there. So a frame
// that arrives while the mapping side is busy, and every frame after it until the backlog is
// cleared, is first tracked against the keyframe the tracking side holds and its pose told at once
// (System::Preview: what a live application takes), then kept here; each call takes the waiting
// frames in order, each once the mapping side has settled, as the sequential run does, until the
// next frame's release (its first pose comes first) and never past the newest frame's deadline
// (RealtimeWait: no frame is dropped for it). With a latency target (RealtimeWait) no frame waits
// here. The mapping side settles a keyframe in tens of milliseconds and the tracking side takes a
// frame in a few, so the backlog of an adjustment is cleared within a few frames of its end. A frame that waited kMaxWaitMs is taken at once against
// whatever is published (a loop adjustment of several seconds would otherwise hold everything up).
#pragma once

#include <chrono>
#include <deque>
#include <optional>

#include "dsm/image/image.h"

namespace dsm {

struct WaitingFrame {
  int index = -1;
  Image<float> image;
  std::chrono::steady_clock::time_point released, taken;
  std::optional<std::chrono::steady_clock::time_point> first_posed;  // System::Preview's.
};

struct FrameBacklog {
  static constexpr double kMaxWaitMs = 1000.0;
  std::deque<WaitingFrame> frames;
  int deferred = 0;  // Frames that waited here.
  int overdue = 0;   // Of those, the ones taken after kMaxWaitMs, the mapping side still busy.
  size_t max_size = 0;
};

}  // namespace dsm
