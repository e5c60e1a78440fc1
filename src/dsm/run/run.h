// SPDX-License-Identifier: MIT
// Running the system over a dataset and writing what a user evaluates:
//   keyframes.tum, frames.tum   world_from_cam poses (TUM format, nanosecond timestamps)
//   stats.json                  counts, timings, latency, memory, map size
//   eval.json                   Sim(3)-aligned ATE of keyframes and frames (with ground truth)
//   map.ply, keyframes.ply      the map's points and keyframe centres (map_export.h; not with
//                               RunOptions::write_map false)
//   report.html                 the run's report page (report/report.h; not with write_report false)
//   RunOptions::save_map        the maps as a map file (mapfile/map_file.h), when set
// With RunOptions::load_map the maps of that file come first (map 0 is its first map).
// A run that starts further maps (relocalisation kept failing) writes each into map_1/, map_2/, ...
#pragma once

#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "dsm/io/dataset.h"
#include "dsm/io/live_camera.h"
#include "dsm/system/options.h"

namespace dsm {

// How frames are fed to the system.
enum class Pace {
  kFree,        // Tracking and mapping on two threads; each frame as soon as tracking takes it.
  kSequential,  // One thread; each keyframe mapped before the next frame (deterministic).
  kRealtime,    // Two threads; frames released at their recorded timestamps, as by a live camera:
                // a frame superseded by a newer one while tracking was busy is dropped.
};
std::string PaceName(Pace pace);
Pace ParsePace(const std::string& name, const std::string& where);  // free | sequential | realtime

struct RunOptions {
  SystemOptions system;
  Pace pace = Pace::kFree;
  int workers = 0;  // Threads of the parallel loops (TBB) in each side; 0: one per core.
  int start = 0;   // First frame index.
  int end = -1;    // One past the last frame (-1: to the end).
  bool quiet = false;  // No progress and no event lines on stdout.
  // Progress (progress.h) when stdout is not a terminal: a line every this many seconds.
  double progress_interval_s = 10.0;
  // Realtime pace: a frame that comes while the mapping side is busy is told a first pose at once
  // and waits, with the frames after it, until the mapping side has settled (frame_backlog.h). With
  // a finite target instead, a frame waits for a keyframe still being mapped (System::Process
  // wait_until) until the next frame comes, never so long that a frame is dropped, and while all
  // but a few keep their latency within it (realtime_wait.h). 0: never wait (frames track against
  // the previous keyframe).
  double realtime_latency_target_ms = std::numeric_limits<double>::infinity();
  bool global_ba = false;  // One bundle adjustment of the whole map after the last frame.
  // Diagnostic, with ground truth: after the outputs are written, the whole map is bundle-adjusted
  // again from the true keyframe poses (System::AdjustWholeMapFrom); eval.json
  // "keyframes_truth_ba" and keyframes_truth_ba.tum give where it ends.
  bool truth_ba = false;
  bool write_map = true;   // map.ply and keyframes.ply beside the trajectories.
  bool write_report = true;  // report.html (report/report.h) in the output folder.
  // Non-empty: every map of the run is written to this map file (mapfile/map_file.h) at the end.
  std::filesystem::path save_map;
  // Non-empty: the run's poses, keyframe images, map points and trajectory are written to this
  // MCAP file at the end (mcap_export.h).
  std::filesystem::path mcap;
  // Non-empty: the maps of this map file are taken up first (System::RestoreMap): the run
  // relocalises in them where the camera starts in a known place, writes its poses in that map's
  // frame and scale and extends it; elsewhere it starts a new map as usual. Output folder 0 is the
  // file's first map; keyframes.tum holds the keyframes this run added.
  std::filesystem::path load_map;
  // With load_map: localise in its maps without changing them (System::LoadedMapUse::kLocalize):
  // the keyframes the run makes are temporary, retired once the camera is back in the loaded map;
  // save_map then writes the loaded maps as they were, and a new map started where the camera
  // is in none of them is left out of it.
  bool localize = false;
  // >= 0: the live viewer (live_view.h) on this localhost port (0: a free one), its address printed.
  int view_port = -1;
  // With the live viewer: before the first frame, wait up to this long for a browser to connect,
  // so that it sees the run from its start (0: do not wait).
  double view_wait_s = 0.0;
  // Non-empty: per-keyframe diagnostics there (debug_writer.h); they need the sequential pace.
  std::filesystem::path debug_dir;
};

struct RunSummary {
  nlohmann::json stats;
  // {"keyframes": ..., "frames": ...}; with the global BA also "keyframes_before_global_ba", with
  // the truth BA "keyframes_truth_ba".
  std::optional<nlohmann::json> eval;
  std::string line;                    // One-line summary.
  int interrupt_signal = 0;  // The signal that stopped the run early (interrupt.h), or 0.
};

// Throws InputError for bad ranges or fewer than two frames. A frame whose file cannot be used is
// skipped with a warning on stderr naming it (stats: frames_skipped, skipped_frames). After SIGINT /
// SIGTERM (interrupt.h; the caller installs the handlers) the run stops after the current frame and
// writes its outputs (stats: "interrupted": true). A damaged recording (DamagedRecordingError)
// stops the run at the frame it could not read: the outputs are written (stats: "damaged_input")
// and then an InputError says where.
RunSummary RunDataset(const Dataset& dataset, const RunOptions& options, const std::filesystem::path& out_dir);

// A run on a live camera's frames as it captures them (io/live_camera.h), in the realtime pace,
// until its stream ends, stalls, or SIGINT / SIGTERM; writes what RunDataset writes, and
// stats.json "live": its source, frames_captured, how it ended ("ended", "stalled",
// "interrupted", "frame size") and the message. Throws InputError once the outputs are written
// when a frame's size did not fit the calibration, and when no frame came at all.
RunSummary RunCamera(LiveCamera& camera, const RunOptions& options, const std::filesystem::path& out_dir);

}  // namespace dsm
