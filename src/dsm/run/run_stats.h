// SPDX-License-Identifier: MIT
// stats.json and the one-line summary of a run (run.h): what the maps counted (SystemStats of
// every map taken as one, map_run.h), what the frame loop counted (FeedRecord: frames dropped and
// skipped, latencies, the realtime backlog), one row per map, and what a run in a loaded map added
// to it. Each map's eval.json is written on the way (EvaluateMap).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/geometry/camera.h"
#include "dsm/io/dataset.h"
#include "dsm/run/frame_backlog.h"
#include "dsm/run/map_run.h"
#include "dsm/run/run.h"

namespace dsm {

// What the frame loop (dataset_run.h) counted.
struct FeedRecord {
  int last_frame = -1;  // The last frame taken (processed or skipped).
  int dropped = 0;      // Realtime: frames superseded by a newer one while tracking was busy.
  std::vector<int> skipped;  // Frames whose file could not be used.
  int interrupt_signal = 0;  // The signal that stopped the run (interrupt.h), or 0.
  std::string damaged_input;  // Why a damaged recording stopped the run (DamagedRecordingError), or empty.
  // Frame release to its first pose, and to the pose the run keeps.
  std::vector<double> latency_ms, latency_final_ms;
  int posed_before_wait = 0;  // Frames told their pose before they waited for a keyframe being mapped.
  int relocalised_in_loaded_at = -1;  // The first frame a loaded map took.
  // Per settled frame: "frame", "tracking_ms", "wait_ms", "tracking_rmse" (parallel arrays; rmse
  // 0 where the frame was not tracked).
  nlohmann::json per_frame = {{"frame", nlohmann::json::array()},
                              {"tracking_ms", nlohmann::json::array()},
                              {"wait_ms", nlohmann::json::array()},
                              {"tracking_rmse", nlohmann::json::array()}};
  double process_s = 0.0;  // From the first frame's release to the end of the last one's mapping.
};

// Time span of frames first..last as the camera recorded them, one frame interval per frame (0 for
// a single frame).
double RecordingSpan(const Dataset& dataset, int first, int last);

nlohmann::json CameraJson(const PinholeCamera& camera);

// stats.json (without "wall_s", "peak_rss_mb" and "map_saved", which the run adds as it ends)
// and the summary line; evaluates each map of `maps` (EvaluateMap: its eval.json), the first one's
// evaluation the summary's. `map_loaded`: stats.json's "map_loaded" (null: no map file).
RunSummary SummariseRun(const Dataset& dataset, const RunOptions& options, const PinholeCamera& camera,
                        const FeedRecord& fed, const FrameBacklog& backlog, std::vector<MapRun>* maps,
                        const nlohmann::json& map_loaded, const std::filesystem::path& out_dir);

}  // namespace dsm
