// SPDX-License-Identifier: MIT
#include "dsm/run/map_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "dsm/eval/metrics.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/run/map_export.h"
#include "dsm/run/mcap_export.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

// The evaluation of a map's trajectories: Sim(3)-aligned (a monocular map has no metres).
EvalOptions Sim3Evaluation() {
  EvalOptions eval;
  eval.align = Alignment::kSim3;
  return eval;
}

// RunOptions::truth_ba: the ground truth at the map's keyframes, moved into the map's frame and
// scale (Sim(3) on the keyframes), set as their poses, and the whole map adjusted from there.
// Needs three keyframes with ground truth.
std::optional<Trajectory> AdjustFromTruth(System& system, const Trajectory& ground_truth, const Trajectory& keyframes) {
  if (keyframes.size() < 3) return std::nullopt;
  const EvalOptions eval = Sim3Evaluation();
  const EvalResult kf = Evaluate(ground_truth, keyframes, eval);
  system.AdjustWholeMapFrom(ReferenceInEstimateFrame(ground_truth, keyframes, kf, eval));
  return system.KeyframeTrajectory();
}

}  // namespace

void WriteJson(const fs::path& path, const nlohmann::json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path.string() + ": cannot write file");
}

// Ends a map: waits for its mapping, runs the global BA when asked, writes its trajectories (and,
// with write_map, its points and keyframes as PLY); then, given `truth` (RunOptions::truth_ba),
// adjusts the map from the true poses (keyframes_truth_ba.tum).
MapRun CloseMap(System& system, const fs::path& dir, const Atlas::Spans& spans, bool global_ba,
                const PinholeCamera& camera, bool write_map, const Trajectory* truth, bool keep_for_mcap) {
  system.Finish();
  MapRun m;
  m.dir = dir;
  m.spans = spans;
  if (!spans.empty()) {
    m.first_frame = spans.front().first;
    m.last_frame = spans.back().second;
  }
  if (global_ba) {
    m.before_global_ba = system.KeyframeTrajectory();
    system.RunGlobalBundleAdjustment();
  }
  m.keyframes = system.KeyframeTrajectory();
  m.frames = system.FrameTrajectory();
  m.stats = system.stats();
  m.map_points = system.NumMapPoints();
  m.loaded_keyframes = system.loaded_keyframes();
  m.loaded_points = system.loaded_points();
  m.retired_keyframes = system.retired_keyframes();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder (" + ec.message() + ")");
  WriteTumTrajectory(dir / "keyframes.tum", m.keyframes);
  WriteTumTrajectory(dir / "frames.tum", m.frames);
  const PlyCloud points = MapPointCloud(system.map(), camera);
  for (const Eigen::Vector3f& x : points.xyz) {
    m.bounds_min = m.bounds_min.cwiseMin(x);
    m.bounds_max = m.bounds_max.cwiseMax(x);
  }
  if (write_map) {
    WritePly(dir / "map.ply", points);
    WritePly(dir / "keyframes.ply", KeyframeCloud(system.map()));
  }
  if (keep_for_mcap) {
    m.points = points;
    m.keyframe_images = KeyframeImages(system.map());
  }
  if (truth) {
    m.truth_ba = AdjustFromTruth(system, *truth, m.keyframes);
    if (m.truth_ba) WriteTumTrajectory(dir / "keyframes_truth_ba.tum", *m.truth_ba);
  }
  return m;
}

// Sim(3) evaluation of a map's trajectories (with at least three poses each), written to its
// eval.json; appends ", keyframe ATE ..." to `line`.
void EvaluateMap(const Dataset& dataset, MapRun* m, std::string* line) {
  if (!dataset.HasGroundTruth() || m->keyframes.size() < 3 || m->frames.size() < 3) return;
  const EvalOptions eval = Sim3Evaluation();
  const EvalResult kf = Evaluate(dataset.ground_truth, m->keyframes, eval);
  const EvalResult fr = Evaluate(dataset.ground_truth, m->frames, eval);
  m->eval = nlohmann::json{{"keyframes", ToJson(kf)}, {"frames", ToJson(fr)}};
  // The ground truth in the map's frame, beside the frames (the report draws and compares them).
  WriteTumTrajectory(m->dir / "groundtruth_in_map.tum",
                     ReferenceInEstimateFrame(dataset.ground_truth, m->frames, fr, eval));
  char text[256];
  std::snprintf(text, sizeof(text), ", keyframe ATE %.2f mm, frame ATE %.2f mm (Sim(3))", 1000.0 * kf.ape.rmse,
                1000.0 * fr.ape.rmse);
  *line += text;
  if (m->before_global_ba) {
    const EvalResult b = Evaluate(dataset.ground_truth, *m->before_global_ba, eval);
    (*m->eval)["keyframes_before_global_ba"] = ToJson(b);
    std::snprintf(text, sizeof(text), ", before global BA %.2f mm", 1000.0 * b.ape.rmse);
    *line += text;
  }
  if (m->truth_ba) {
    const EvalResult t = Evaluate(dataset.ground_truth, *m->truth_ba, eval);
    (*m->eval)["keyframes_truth_ba"] = ToJson(t);
    std::snprintf(text, sizeof(text), ", adjusted from the true poses %.2f mm", 1000.0 * t.ape.rmse);
    *line += text;
  }
  WriteJson(m->dir / "eval.json", *m->eval);
}

// The stats of all maps as one: counts summed, per-frame and per-keyframe lists concatenated.
SystemStats Combined(const std::vector<MapRun>& maps) {
  SystemStats all = maps.front().stats;
  const auto append = [](auto* to, const auto& from) { to->insert(to->end(), from.begin(), from.end()); };
  for (size_t i = 1; i < maps.size(); ++i) {
    const SystemStats& s = maps[i].stats;
    // A map taken in by the first one (atlas.h) started the run's map before it.
    if (maps[i].merged_into == 0 && s.initialized_at_frame >= 0 &&
        (all.initialized_at_frame < 0 || s.initialized_at_frame < all.initialized_at_frame)) {
      all.initialized_at_frame = s.initialized_at_frame;
      all.initialization = s.initialization;
    }
    all.frames += s.frames;
    all.frames_tracked += s.frames_tracked;
    all.keyframes += s.keyframes;
    all.frames_lost += s.frames_lost;
    all.relocalisations += s.relocalisations;
    append(&all.lost_episodes, s.lost_episodes);
    append(&all.relocalised, s.relocalised);
    append(&all.tracking_ms, s.tracking_ms);
    append(&all.tracing_ms, s.tracing_ms);
    append(&all.mapping_ms, s.mapping_ms);
    append(&all.pba_ms, s.pba_ms);
    append(&all.young_map_ba_ms, s.young_map_ba_ms);
    append(&all.loop_ba_ms, s.loop_ba_ms);
    all.points_created += s.points_created;
    all.reobservations += s.reobservations;
    all.covisible_keyframes_selected += s.covisible_keyframes_selected;
    append(&all.per_keyframe, s.per_keyframe);
    all.keyframe_queue_max = std::max(all.keyframe_queue_max, s.keyframe_queue_max);
    all.keyframe_waits += s.keyframe_waits;
    all.keyframe_wait_timeouts += s.keyframe_wait_timeouts;
    all.keyframe_retracks += s.keyframe_retracks;
    all.adjustments_yielded += s.adjustments_yielded;
    all.traces_skipped += s.traces_skipped;
    all.brightness_holds += s.brightness_holds;
    all.pyramids_rebuilt += s.pyramids_rebuilt;
    all.keyframes_culled += s.keyframes_culled;
    all.loops_detected += s.loops_detected;
    append(&all.loops_closed, s.loops_closed);
    append(&all.maps_merged, s.maps_merged);
    all.points_rehosted += s.points_rehosted;
    all.points_dropped += s.points_dropped;
    all.pyramids_loaded_max = std::max(all.pyramids_loaded_max, s.pyramids_loaded_max);
  }
  return all;
}

nlohmann::json RelocalisedJson(const SystemStats& s) {
  nlohmann::json relocalised = nlohmann::json::array();
  for (const SystemStats::Relocalisation& r : s.relocalised)
    relocalised.push_back({{"frame", r.frame},
                           {"keyframe", r.keyframe},
                           {"frames_lost", r.frames_lost},
                           {"predicted", r.predicted},
                           {"inlier_ratio", r.inlier_ratio},
                           {"inlier_level", r.inlier_level},
                           {"residual_ratio", r.residual_ratio},
                           {"margin", r.margin}});
  return relocalised;
}

nlohmann::json LoopsClosedJson(const SystemStats& s) {
  nlohmann::json loops = nlohmann::json::array();
  for (const SystemStats::LoopClosure& l : s.loops_closed)
    loops.push_back({{"frame", l.frame},
                     {"keyframe", l.keyframe},
                     {"candidate_keyframe", l.candidate},
                     {"inliers", l.inliers},
                     {"translation_share", l.translation_share},
                     {"rotation_deg", l.rotation_deg},
                     {"scale", l.scale},
                     {"residual_ratio", l.residual_ratio},
                     {"shift_px", l.shift_px},
                     {"correction_share", l.correction_share},
                     {"margin", l.margin},
                     {"ms", l.ms}});
  return loops;
}

nlohmann::json MapsMergedJson(const SystemStats& s) {
  nlohmann::json merges = nlohmann::json::array();
  for (const SystemStats::MapMerge& m : s.maps_merged)
    merges.push_back({{"frame", m.frame},
                      {"keyframe", m.keyframe},
                      {"candidate_keyframe", m.candidate},
                      {"map", m.map},
                      {"keyframes", m.keyframes},
                      {"points", m.points},
                      {"inliers", m.inliers},
                      {"scale", m.scale},
                      {"ms", m.ms}});
  return merges;
}

}  // namespace dsm
