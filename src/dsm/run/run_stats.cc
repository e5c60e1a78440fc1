// SPDX-License-Identifier: MIT
#include "dsm/run/run_stats.h"

#include <algorithm>
#include <cstdio>

namespace dsm {

namespace fs = std::filesystem;

namespace {

nlohmann::json TimingStats(std::vector<double> ms) {
  if (ms.empty()) return {{"median", 0.0}, {"p90", 0.0}, {"max", 0.0}, {"mean", 0.0}, {"count", 0}};
  std::sort(ms.begin(), ms.end());
  double sum = 0.0;
  for (double v : ms) sum += v;
  const auto at = [&](double q) { return ms[std::min(ms.size() - 1, static_cast<size_t>(q * ms.size()))]; };
  return {{"median", at(0.5)}, {"p90", at(0.9)}, {"max", ms.back()}, {"mean", sum / ms.size()}, {"count", ms.size()}};
}

// Median, p90 and max of the latencies `ms`.
nlohmann::json LatencyStats(std::vector<double> ms) {
  const nlohmann::json t = TimingStats(std::move(ms));
  return {{"median", t["median"]}, {"p90", t["p90"]}, {"max", t["max"]}};
}

// "per_keyframe": one object per keyframe, with its adjustments.
nlohmann::json PerKeyframeJson(const SystemStats& s) {
  nlohmann::json per_keyframe = nlohmann::json::array();
  for (const SystemStats::KeyframeLog& k : s.per_keyframe) {
    per_keyframe.push_back({{"frame", k.frame}, {"points_created", k.points_created},
                            {"reobservations", k.reobservations}, {"covisible", k.covisible},
                            {"points_seen", k.points_seen}, {"old_points_seen", k.old_points_seen},
                            {"pba", {{"keyframes", k.pba_keyframes}, {"fixed_keyframes", k.pba_fixed_keyframes},
                                     {"points", k.pba_points}, {"observations", k.pba_observations},
                                     {"iterations", k.pba_iterations}, {"ms", k.pba_ms}}}});
    if (k.young_map_ba_keyframes > 0)
      per_keyframe.back()["young_map_ba"] = {{"keyframes", k.young_map_ba_keyframes},
                                              {"ms", k.young_map_ba_ms},
                                              {"iterations", k.young_map_ba_iterations},
                                              {"observations", k.young_map_ba_observations}};
    if (k.loop_ba_keyframes > 0)
      per_keyframe.back()["loop_ba"] = {
          {"keyframes", k.loop_ba_keyframes}, {"ms", k.loop_ba_ms}, {"seam", k.loop_ba_seam}};
    if (k.rejoined)
      per_keyframe.back()["rejoin"] = {
          {"step", k.rejoin_step}, {"degrees", k.rejoin_deg}, {"shift_px", k.rejoin_shift_px}};
  }
  return per_keyframe;
}

// What the maps counted, taken as one.
nlohmann::json MapsStatsJson(const SystemStats& s, int map_points) {
  nlohmann::json created = nlohmann::json::array();
  for (const SystemStats::KeyframeLog& k : s.per_keyframe) created.push_back(k.points_created);
  nlohmann::json j = {
      {"frames", s.frames},
      {"frames_tracked", s.frames_tracked},
      {"frames_lost", s.frames_lost},
      {"lost_episodes", s.lost_episodes},
      {"relocalisations", s.relocalisations},
      {"keyframes", s.keyframes},
      {"map_points", map_points},
      {"initialized_at_frame", s.initialized_at_frame},
      {"initialization", s.initialization},
      {"image_noise_sigma", s.image_noise_sigma},
      {"contrast_floor", s.contrast_floor},
      {"interpolation", s.interpolation},
      {"texture_loss", s.texture_loss},
      {"points_created", s.points_created},
      {"reobservations", s.reobservations},
      {"covisible_keyframes_selected", s.covisible_keyframes_selected},
      {"points_created_per_keyframe", created},
      {"per_keyframe", PerKeyframeJson(s)},
      {"timing_ms", {{"tracking", TimingStats(s.tracking_ms)}, {"tracing", TimingStats(s.tracing_ms)},
                     {"mapping", TimingStats(s.mapping_ms)}, {"pba", TimingStats(s.pba_ms)},
                     {"young_map_ba", TimingStats(s.young_map_ba_ms)}, {"loop_ba", TimingStats(s.loop_ba_ms)}}},
      {"keyframe_queue_max", s.keyframe_queue_max},
      {"keyframe_waits", s.keyframe_waits},
      {"keyframe_wait_timeouts", s.keyframe_wait_timeouts},
      {"keyframe_retracks", s.keyframe_retracks},
      {"adjustments_yielded", s.adjustments_yielded},
      {"traces_skipped", s.traces_skipped},
      {"brightness_holds", s.brightness_holds},
      {"pyramids_rebuilt", s.pyramids_rebuilt},
      // Keyframe culling: the keyframes the maps keep (made, less those culled) and what became
      // of the culled ones' points.
      {"keyframes_culled", s.keyframes_culled},
      {"keyframes_kept", s.keyframes - s.keyframes_culled},
      {"points_rehosted", s.points_rehosted},
      {"points_dropped", s.points_dropped},
      {"pyramids_loaded_max", s.pyramids_loaded_max},
      // Loop closure: places recognised, and the loops closed with their corrections.
      {"loops_detected", s.loops_detected},
      {"loops_closed", LoopsClosedJson(s)},
      {"relocalised", RelocalisedJson(s)},
      {"maps_merged", MapsMergedJson(s)},
  };
  if (s.global_ba_ms >= 0.0) j["timing_ms"]["global_ba"] = s.global_ba_ms;
  return j;
}

// What the frame loop counted, and the speed against the recording: the frames' time span over
// the time spent reading and processing them (mapping included); > 1 is faster than real time.
void AddFeedStats(const Dataset& dataset, int start, const FeedRecord& fed, const FrameBacklog& backlog,
                  nlohmann::json* stats) {
  nlohmann::json& j = *stats;
  j["per_frame"] = fed.per_frame;
  j["frames_dropped"] = fed.dropped;
  j["frames_skipped"] = fed.skipped.size();
  j["skipped_frames"] = fed.skipped;
  j["interrupted"] = fed.interrupt_signal != 0;
  if (!fed.damaged_input.empty()) j["damaged_input"] = fed.damaged_input;
  j["latency_ms"] = LatencyStats(fed.latency_ms);
  j["latency_final_ms"] = LatencyStats(fed.latency_final_ms);
  j["frames_posed_before_wait"] = fed.posed_before_wait;
  j["frames_deferred"] = backlog.deferred;
  j["frames_overdue"] = backlog.overdue;
  j["backlog_max"] = backlog.max_size;
  const int processed = fed.last_frame + 1 - start;  // Frames read or skipped.
  const double recording_s = RecordingSpan(dataset, start, fed.last_frame);
  j["processing_s"] = fed.process_s;
  j["frames_per_second"] = processed / fed.process_s;
  if (recording_s > 0.0) {
    j["recording_s"] = recording_s;
    j["realtime_factor"] = recording_s / fed.process_s;
  }
}

// "N/M frames tracked, K keyframes, P points, initialised at frame F, X fps (Yx real time), ...".
std::string SummaryLine(const SystemStats& s, const nlohmann::json& stats, bool map_loaded,
                        const std::vector<MapRun>& maps) {
  char line[512];
  std::snprintf(line, sizeof(line), "%d/%d frames tracked, %d keyframes, %d points, ", s.frames_tracked, s.frames,
                s.keyframes, stats["map_points"].get<int>());
  std::string summary = line;
  // A run that went on in a loaded map started none of its own.
  if (s.initialized_at_frame >= 0 || !map_loaded)
    summary += "initialised at frame " + std::to_string(s.initialized_at_frame) + ", ";
  std::snprintf(line, sizeof(line), "%.1f fps", stats["frames_per_second"].get<double>());
  summary += line;
  if (stats.contains("realtime_factor")) {
    std::snprintf(line, sizeof(line), " (%.2fx real time)", stats["realtime_factor"].get<double>());
    summary += line;
  }
  if (s.frames_lost > 0) {
    std::snprintf(line, sizeof(line), ", %d lost (%zu episodes, %d relocalised)", s.frames_lost, s.lost_episodes.size(),
                  s.relocalisations);
    summary += line;
  }
  // Maps counted: those that took part (a new map that never started while the camera
  // relocalised in a loaded one does not). Maps merged into another count with it.
  const size_t maps_made = std::count_if(maps.begin(), maps.end(), [](const MapRun& m) {
    return m.merged_into < 0 && (m.stats.keyframes > 0 || m.loaded_keyframes > 0);
  });
  if (maps_made > 1) summary += ", " + std::to_string(maps_made) + " maps";
  if (!s.maps_merged.empty()) summary += ", " + std::to_string(s.maps_merged.size()) + " merged";
  return summary;
}

// stats.json's row of map `m`, evaluated (its eval.json written).
nlohmann::json MapRow(const MapRun& m, const fs::path& out_dir) {
  if (m.merged_into >= 0) {
    return {{"dir", nullptr}, {"merged_into", m.merged_into}, {"frames_tracked", m.stats.frames_tracked},
            {"keyframes", m.stats.keyframes}, {"initialized_at_frame", m.stats.initialized_at_frame}};
  }
  nlohmann::json j = {{"dir", fs::relative(m.dir, out_dir).string()}, {"first_frame", m.first_frame},
                      {"last_frame", m.last_frame}, {"spans", m.spans}, {"frames_tracked", m.stats.frames_tracked},
                      {"keyframes", m.stats.keyframes}, {"map_points", m.map_points},
                      {"initialized_at_frame", m.stats.initialized_at_frame},
                      {"loaded", m.loaded_keyframes > 0}};
  if (m.loaded_keyframes > 0) {
    j["keyframes_loaded"] = m.loaded_keyframes;
    j["points_loaded"] = m.loaded_points;
  }
  if (m.eval) j["keyframe_ate_m"] = (*m.eval)["keyframes"]["ape"]["rmse"];
  if (m.map_points > 0) {
    j["bounds"] = {{"min", {m.bounds_min.x(), m.bounds_min.y(), m.bounds_min.z()}},
                   {"max", {m.bounds_max.x(), m.bounds_max.y(), m.bounds_max.z()}}};
  }
  return j;
}

// A run in a loaded map: what it added to the loaded maps (a new map that started meanwhile has
// its own row in "maps"). Localising, they are temporary: those retired are gone again, the rest
// go with the run.
void AddLoadedMapStats(const RunOptions& options, const FeedRecord& fed, const std::vector<MapRun>& maps,
                       const nlohmann::json& map_loaded, RunSummary* summary) {
  nlohmann::json& j = summary->stats;
  j["map_loaded"] = map_loaded;
  j["relocalised_in_loaded_map_at_frame"] =
      fed.relocalised_in_loaded_at >= 0 ? nlohmann::json(fed.relocalised_in_loaded_at) : nlohmann::json(nullptr);
  int keyframes_added = 0, points_added = 0, retired = 0;
  for (const MapRun& m : maps) {
    if (m.loaded_keyframes == 0) continue;
    keyframes_added += m.stats.keyframes;
    points_added += m.stats.points_created;
    retired += m.retired_keyframes;
  }
  j["keyframes_added"] = keyframes_added;
  j["points_added"] = points_added;
  j["localize"] = options.localize;
  if (options.localize) j["keyframes_retired"] = retired;
  summary->line += fed.relocalised_in_loaded_at >= 0
                       ? "; relocalised in the loaded map at frame " + std::to_string(fed.relocalised_in_loaded_at)
                       : "; never relocalised in the loaded map";
}

}  // namespace

double RecordingSpan(const Dataset& dataset, int first, int last) {
  const int n = last + 1 - first;
  if (n < 2) return 0.0;
  return 1e-9 * static_cast<double>(dataset.frames[last].t_ns - dataset.frames[first].t_ns) * n / (n - 1);
}

nlohmann::json CameraJson(const PinholeCamera& c) {
  return {{"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}};
}

RunSummary SummariseRun(const Dataset& dataset, const RunOptions& options, const PinholeCamera& camera,
                        const FeedRecord& fed, const FrameBacklog& backlog, std::vector<MapRun>* maps,
                        const nlohmann::json& map_loaded, const fs::path& out_dir) {
  const SystemStats s = Combined(*maps);
  int map_points = 0;
  for (const MapRun& m : *maps) map_points += m.map_points;
  RunSummary summary;
  summary.stats = MapsStatsJson(s, map_points);
  summary.stats["dataset"] = dataset.root.string();
  summary.stats["camera"] = CameraJson(camera);
  summary.stats["line_delay_us"] = dataset.line_delay_us;
  summary.stats["line_delay_source"] = LineDelaySourceName(dataset.line_delay_source);
  summary.stats["mode"] = MapModeName(options.system.mode);
  summary.stats["pace"] = PaceName(options.pace);
  AddFeedStats(dataset, options.start, fed, backlog, &summary.stats);
  summary.interrupt_signal = fed.interrupt_signal;
  summary.line = SummaryLine(s, summary.stats, !map_loaded.is_null(), *maps);
  nlohmann::json map_list = nlohmann::json::array();
  for (size_t k = 0; k < maps->size(); ++k) {
    MapRun& m = (*maps)[k];
    std::string map_line;
    EvaluateMap(dataset, &m, &map_line);
    if (k == 0) {
      summary.eval = m.eval;
      summary.line += map_line;
    } else if (!map_line.empty()) {
      summary.line += "; map " + std::to_string(k) + map_line;
    }
    map_list.push_back(MapRow(m, out_dir));
  }
  summary.stats["maps"] = map_list;
  if (!map_loaded.is_null()) AddLoadedMapStats(options, fed, *maps, map_loaded, &summary);
  return summary;
}

}  // namespace dsm
