// SPDX-License-Identifier: MIT
// The run report: report.html, one self-contained page (it needs no network to be viewed) with a 3D
// view of the map and plots of the run's statistics; web/src/report.js draws it.
//
// ReportData reads everything from a run's output folder, so that `dsm run` and `dsm report
// RUN_DIR` build the same page:
//   stats.json                          required
//   per map folder (stats maps[].dir):  keyframes.tum (required), frames.tum, keyframes.ply, map.ply,
//                                       groundtruth_in_map.tum and eval.json (when present)
// The document the page reads:
//   title, summary {frames, frames_tracked, keyframes, map_points, mode, pace, frames_per_second,
//                   realtime_factor, frames_lost, relocalisations, interrupted, keyframe_ate_mm,
//                   map_loaded {file, maps, keyframes, points} (dsm run --load-map)}
//   camera {width, height, fx, fy, cx, cy}
//   maps [{dir, points {count, xyz: base64 float32 x y z..., grey: base64 uint8, loaded: the first
//                       `loaded` points are a loaded map's (stats maps[].keyframes_loaded)},
//          keyframes [{id, frame, t, p [x y z], q [qx qy qz qw]}] (world_from_cam; the run's own,
//                     ids after a loaded map's),
//          groundtruth [[t x y z]...] (in the map's frame), covisibility [[keyframe id, id]...]}]
//   errors [{map, t [s], error_mm [...]}]  position error of the frames after Sim(3) alignment
//   per_frame {frame [...], tracking_ms [...]}
//   per_keyframe {frame, pba_ms, points_created, reobservations: [...]}
//   lost_episodes [[first, last]...]
// Times t are seconds since the run's first frame.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/lie/se3.h"

// The page's script (web/, bundled at build time; report_bundle.S), NUL-terminated.
extern "C" const char dsm_report_script[];

namespace dsm {

// Throws InputError naming the file when a required output is missing or malformed.
nlohmann::json ReportData(const std::filesystem::path& run_dir);

// The HTML page with `data` and the script inlined. `live`: the page also listens on the WebSocket
// /ws of the server that served it for new documents (dsm run --view).
std::string ReportPage(const nlohmann::json& data, bool live = false);

// Writes run_dir/report.html from the run's outputs.
void WriteReport(const std::filesystem::path& run_dir);

// The page's title for a dataset path: its folder's (or video file's) name.
std::string ReportTitle(const std::filesystem::path& dataset);

// Parts of the document, for its other builder (the live viewer, run/live_view.h):
// {count, xyz, grey} from x y z triples and grey values ...
nlohmann::json PointsJson(const std::vector<float>& xyz, const std::vector<uint8_t>& grey);
// ... and {id, frame, t, p, q} of a keyframe.
nlohmann::json KeyframeJson(int id, int frame, double t, const SE3d& world_from_cam);

}  // namespace dsm
