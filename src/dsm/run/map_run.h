// SPDX-License-Identifier: MIT
// One map of a run (atlas.h) as it ends: its trajectories, PLY files and evaluation written into
// its folder, and the stats of all maps of the run taken as one.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/image/image.h"
#include "dsm/io/dataset.h"
#include "dsm/io/ply.h"
#include "dsm/system/atlas.h"
#include "dsm/system/system.h"

namespace dsm {

// Writes `j` to `path`, indented; InputError naming the path when it cannot.
void WriteJson(const std::filesystem::path& path, const nlohmann::json& j);

// One map of the run (atlas.h), as it ended.
struct MapRun {
  std::filesystem::path dir;  // Where its trajectories (and evaluation) are written.
  int first_frame = -1, last_frame = -1;  // Of the frames it took (-1: none) ...
  Atlas::Spans spans;                     // ... in spans (more than one: it was resumed).
  SystemStats stats;
  int map_points = 0;
  int loaded_keyframes = 0;  // Of a map loaded from a map file (System::RestoreMap).
  int loaded_points = 0;
  int retired_keyframes = 0;  // Temporary keyframes of a localisation (RunOptions::localize).
  int merged_into = -1;       // The map that took it in (atlas.h; -1: none): nothing written.
  // Corners of the box around its points (world, the map's scale); min > max when it has none.
  Eigen::Vector3f bounds_min = Eigen::Vector3f::Constant(INFINITY), bounds_max = -bounds_min;
  Trajectory keyframes, frames;
  std::optional<Trajectory> before_global_ba;
  std::optional<Trajectory> truth_ba;  // Keyframes after System::AdjustWholeMapFrom(the truth).
  std::optional<nlohmann::json> eval;
  // Kept for the MCAP file (RunOptions::mcap) when it is asked for: its points and keyframe images.
  PlyCloud points;
  std::vector<std::pair<int64_t, Image<uint8_t>>> keyframe_images;
};

// Ends a map: waits for its mapping, runs the global BA when asked, writes its trajectories (and,
// with write_map, its points and keyframes as PLY); then, given `truth` (RunOptions::truth_ba),
// adjusts the map from the true poses (keyframes_truth_ba.tum).
MapRun CloseMap(System& system, const std::filesystem::path& dir, const Atlas::Spans& spans, bool global_ba,
                const PinholeCamera& camera, bool write_map, const Trajectory* truth, bool keep_for_mcap = false);

// Sim(3) evaluation of a map's trajectories (with at least three poses each), written to its
// eval.json; appends ", keyframe ATE ..." to `line`.
void EvaluateMap(const Dataset& dataset, MapRun* m, std::string* line);

// The stats of all maps as one: counts summed, per-frame and per-keyframe lists concatenated.
SystemStats Combined(const std::vector<MapRun>& maps);

// stats.json's `relocalised`, `loops_closed` and `maps_merged`: one object per event.
nlohmann::json RelocalisedJson(const SystemStats& s);
nlohmann::json LoopsClosedJson(const SystemStats& s);
nlohmann::json MapsMergedJson(const SystemStats& s);

}  // namespace dsm
