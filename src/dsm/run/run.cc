// SPDX-License-Identifier: MIT
#include "dsm/run/run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>
#include <tbb/global_control.h>

#include "dsm/eval/metrics.h"
#include "dsm/geometry/undistorter.h"
#include "dsm/config/option_registry.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/mapfile/map_file.h"
#include "dsm/report/report.h"
#include "dsm/run/debug_writer.h"
#include "dsm/run/frame_backlog.h"
#include "dsm/run/frame_reader.h"
#include "dsm/run/interrupt.h"
#include "dsm/run/live_view.h"
#include "dsm/run/map_set.h"
#include "dsm/run/map_export.h"
#include "dsm/run/map_run.h"
#include "dsm/run/progress.h"
#include "dsm/run/realtime_wait.h"
#include "dsm/system/system.h"
#include "dsm/util/check.h"
#include "dsm/util/version.h"

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

// The most resident memory the process has had so far.
double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes.
}

// Time span of frames first..last as the camera recorded them, one frame interval per frame (0 for
// a single frame).
double RecordingSpan(const Dataset& dataset, int first, int last) {
  const int n = last + 1 - first;
  if (n < 2) return 0.0;
  return 1e-9 * static_cast<double>(dataset.frames[last].t_ns - dataset.frames[first].t_ns) * n / (n - 1);
}

nlohmann::json CameraJson(const PinholeCamera& c) {
  return {{"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}};
}

// RunOptions::load_map: its maps, each taken up by a System of `make`, and the options that made
// them (*options); none without a file.
template <typename Make>
std::vector<std::unique_ptr<System>> LoadMaps(const fs::path& file, const PinholeCamera& camera, const Make& make,
                                              System::LoadedMapUse use, std::string* options) {
  std::vector<std::unique_ptr<System>> systems;
  if (file.empty()) return systems;
  MapFile read = ReadMapFile(file);
  *options = read.options;
  for (StoredMap& stored : MapsToTakeUp(file, std::move(read), camera)) {
    systems.push_back(make());
    systems.back()->RestoreMap(std::move(stored), use);
  }
  return systems;
}

}  // namespace

Pace ParsePace(const std::string& name, const std::string& where) {
  for (Pace pace : {Pace::kFree, Pace::kSequential, Pace::kRealtime})
    if (name == PaceName(pace)) return pace;
  throw InputError(where + ": expected free, sequential or realtime, got '" + name + "'");
}

std::string PaceName(Pace pace) {
  switch (pace) {
    case Pace::kFree: return "free";
    case Pace::kSequential: return "sequential";
    case Pace::kRealtime: return "realtime";
  }
  return "?";
}

RunSummary RunDataset(const Dataset& dataset, const RunOptions& options, const fs::path& out_dir) {
  const auto wall0 = std::chrono::steady_clock::now();
  options.system.Validate();
  const int n = static_cast<int>(dataset.size());
  const int end = options.end < 0 ? n : std::min(options.end, n);
  if (options.start < 0 || options.start >= end) {
    throw InputError("--start/--end select no frames (the dataset has " + std::to_string(n) + ")");
  }
  if (end - options.start < 2) {
    throw InputError(dataset.root.string() + ": a run needs at least two frames (" +
                     std::to_string(end - options.start) + " selected)");
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir.string() + ": cannot create the output folder (" + ec.message() + ")");

  if (!options.debug_dir.empty() && options.pace != Pace::kSequential) {
    throw InputError("--debug needs the sequential pace (--sequential): it reads the map after every keyframe");
  }
  if (options.workers < 0) throw InputError("--workers must be >= 0");
  std::optional<tbb::global_control> workers;
  if (options.workers > 0) workers.emplace(tbb::global_control::max_allowed_parallelism, options.workers);
  SystemOptions system_options = options.system;
  system_options.threaded = options.pace != Pace::kSequential;
  system_options.wait_for_mapping = options.pace != Pace::kRealtime;
  system_options.yield_adjustments = options.pace == Pace::kRealtime;
  system_options.keyframe_features = options.pace == Pace::kRealtime;
  system_options.skip_traces_while_mapping = options.pace == Pace::kFree;
  system_options.map_snapshots = options.view_port >= 0;
  system_options.line_delay_s = dataset.line_delay_us * 1e-6;
  const Undistorter undistorter = FrameUndistorter(dataset, options.system);
  const auto map_dir = [&](size_t index) { return index == 0 ? out_dir : out_dir / ("map_" + std::to_string(index)); };
  std::optional<DebugWriter> debug;
  if (!options.debug_dir.empty()) debug.emplace(options.debug_dir, dataset, undistorter);
  std::optional<LiveView> live;
  if (options.view_port >= 0) {
    LiveView::Context context{ReportTitle(dataset.root), MapModeName(options.system.mode), PaceName(options.pace),
                              CameraJson(undistorter.output())};
    live.emplace(options.view_port, dataset, context);
    std::printf("view: http://127.0.0.1:%d/ (updated while the run goes on)\n", live->port());
    std::fflush(stdout);
    if (options.view_wait_s > 0.0 && !live->WaitForBrowser(options.view_wait_s)) {
      std::printf("view: no browser connected within %g s; the run goes on\n", options.view_wait_s);
      std::fflush(stdout);
    }
  }
  std::optional<std::chrono::steady_clock::time_point> first_posed;  // The current frame's.
  std::vector<std::optional<MapRun>> ended;  // By map id.
  std::vector<std::optional<StoredMap>> stored;  // By map id, with --save-map.
  if (!options.save_map.empty() && fs::is_directory(options.save_map)) {
    throw InputError(options.save_map.string() + ": --save-map names a folder, not a file");
  }
  const auto make_system = [&] {
    auto system = std::make_unique<System>(undistorter.output(), system_options);
    system->SetPoseListener([&first_posed](int, const SE3d&) {
      if (!first_posed) first_posed = std::chrono::steady_clock::now();
    });
    return system;
  };
  // The maps of a map file are read before the run's clock starts (realtime: before the first
  // frame is released).
  if (options.localize && options.load_map.empty()) throw InputError("--localize needs a map to localise in (--load-map)");
  std::string loaded_options;
  std::vector<std::unique_ptr<System>> loaded =
      LoadMaps(options.load_map, undistorter.output(), make_system,
               options.localize ? System::LoadedMapUse::kLocalize : System::LoadedMapUse::kExtend, &loaded_options);
  const int loaded_maps = static_cast<int>(loaded.size());
  nlohmann::json map_loaded;
  if (!loaded.empty()) {
    int keyframes = 0, points = 0;
    for (const auto& system : loaded) keyframes += system->loaded_keyframes(), points += system->loaded_points();
    map_loaded = {{"file", options.load_map.string()}, {"maps", loaded_maps}, {"keyframes", keyframes},
                  {"points", points}};
  }
  const auto process0 = std::chrono::steady_clock::now();
  // Realtime: frame i is released at process0 + (t_i - t_start), as a camera would deliver it.
  const auto release = [&](int i) {
    return process0 + std::chrono::nanoseconds(dataset.frames[i].t_ns - dataset.frames[options.start].t_ns);
  };
  // Free and sequential paces: frames read ahead on the reader's thread. Realtime: a frame is read
  // once released (a live camera cannot be read ahead).
  std::optional<FrameReader> reader;
  if (options.pace != Pace::kRealtime) reader.emplace(dataset, undistorter, options.start, end, 2);
  FramePrefetch prefetch(dataset, end);  // Realtime: the reader's, on this thread.
  // Frame release (free, sequential: the reader hands it over) to its first pose (System::
  // SetPoseListener; a frame without one: to the end of its processing), and to the pose the run
  // keeps (after any wait for a keyframe being mapped).
  std::vector<double> latency_ms, latency_final_ms;
  int posed_before_wait = 0;  // Frames told their pose before they waited for a keyframe being mapped.
  int relocalised_in_loaded_at = -1;  // The first frame a loaded map took.
  MapSet map_set(
      make_system,
      [&](int id, System& system, const MapSet::Spans& spans, int merged_into) {
        if (ended.size() <= static_cast<size_t>(id)) ended.resize(id + 1);
        if (merged_into >= 0) {
          // Its keyframes, points and frames are the other map's now: only its counts stay.
          system.Finish();
          MapRun m;
          m.merged_into = merged_into;
          m.stats = system.stats();
          ended[id] = std::move(m);
          return;
        }
        // A map saved for later sessions is adjusted whole first (System::TakeStoredMap): the
        // trajectories written are the map's as saved.
        const bool saved = !options.save_map.empty() && (!options.localize || system.localizing());
        ended[id] = CloseMap(system, map_dir(id), spans, (options.global_ba || saved) && !system.localizing(),
                             undistorter.output(), options.write_map,
                             options.truth_ba && dataset.HasGroundTruth() ? &dataset.ground_truth : nullptr);
        if (saved) {
          if (stored.size() <= static_cast<size_t>(id)) stored.resize(id + 1);
          stored[id] = system.TakeStoredMap();
        }
      },
      std::move(loaded));
  int dropped = 0;
  std::vector<int> skipped;  // Frames whose file could not be used.
  bool any_frame_used = false;  // A frame of the calibration's size was read.
  int interrupt_signal = 0;  // The signal that stopped the run (interrupt.h), or 0.
  int last_frame = options.start - 1;  // The last frame taken (processed or skipped).
  Progress progress(options.quiet ? nullptr : stdout, isatty(fileno(stdout)) != 0, options.progress_interval_s);
  ProgressState shown;
  shown.total = end - options.start;
  TrackingStatus last_status = TrackingStatus::kInitializing;
  RealtimeWait realtime_wait(options.realtime_latency_target_ms);
  nlohmann::json per_frame = {
      {"frame", nlohmann::json::array()}, {"tracking_ms", nlohmann::json::array()}, {"wait_ms", nlohmann::json::array()}};
  // A frame settled in map `s.map` (map_set.h): its events, diagnostics and progress.
  const auto settle = [&](const MapSet::Settled& s) {
    const FrameReport& r = s.report;
    const int i = r.index;
    if (debug) debug->AddFrame(r, s.map);
    if (debug && r.keyframe && s.map == 0) debug->AddKeyframes(map_set.current());  // The first map's.
    // Events: tracking lost (once per episode), regained, and a map the camera came back to.
    // The first frame in a loaded map is told as such, and the next one, which confirms it, not again.
    const bool first_in_loaded = r.status == TrackingStatus::kOk && s.map < loaded_maps && relocalised_in_loaded_at < 0;
    if (first_in_loaded) relocalised_in_loaded_at = i;
    const bool confirms_first_in_loaded = r.resumed && s.map < loaded_maps && i == relocalised_in_loaded_at + 1;
    if (first_in_loaded) {
      progress.Event("frame " + std::to_string(i) + "  relocalised in the loaded map " + std::to_string(s.map));
    } else if (r.resumed && !confirms_first_in_loaded) {
      progress.Event("frame " + std::to_string(i) + "  back in map " + std::to_string(s.map) + " (relocalised)");
    } else if (r.relocalised || (r.status == TrackingStatus::kLost && last_status != TrackingStatus::kLost)) {
      progress.Event("frame " + std::to_string(i) + "  " + (r.relocalised ? "relocalised" : "tracking lost") +
                     (r.reason.empty() ? "" : "  (" + r.reason + ")"));
    }
    last_status = r.status;
    per_frame["frame"].push_back(i);
    per_frame["tracking_ms"].push_back(r.tracking_ms);
    per_frame["wait_ms"].push_back(r.wait_ms);
    shown.frame = i;
    shown.done = i + 1 - options.start;
    shown.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - process0).count();
    shown.recording_s = RecordingSpan(dataset, options.start, i);
    const System::MapSize size = map_set.current().TrackedMapSize();
    shown.keyframes = size.keyframes;
    shown.points = size.points;
    shown.state = r.status == TrackingStatus::kOk ? "tracking" : r.status == TrackingStatus::kLost ? "lost" : "initialising";
    progress.Update(shown);
    if (live) live->Frame(map_set.current(), shown, per_frame, s.map);
  };
  // Frame i handed to the maps, its latencies and events; `first_pose` told before (Preview).
  const auto take = [&](int i, const Image<float>& image, std::chrono::steady_clock::time_point released,
                        std::optional<std::chrono::steady_clock::time_point> taken,
                        std::optional<std::chrono::steady_clock::time_point> wait_until,
                        std::optional<std::chrono::steady_clock::time_point> first_pose) {
    first_posed = first_pose;
    const std::vector<MapSet::Settled> settled =
        map_set.Process(i, dataset.frames[i].t_ns, image, dataset.frames[i].exposure_ms, wait_until);
    const auto posed = std::chrono::steady_clock::now();
    latency_ms.push_back(std::chrono::duration<double, std::milli>(first_posed.value_or(posed) - released).count());
    latency_final_ms.push_back(std::chrono::duration<double, std::milli>(posed - released).count());
    const FrameReport* r = nullptr;  // This frame's, when settled now.
    for (const MapSet::Settled& st : settled)
      if (st.report.index == i) r = &st.report;
    if (first_pose || (r && r->posed_before_wait)) ++posed_before_wait;
    if (taken) {
      const double busy = r && r->wait_end
                              ? std::chrono::duration<double, std::milli>(posed - *r->wait_end).count()
                              : std::chrono::duration<double, std::milli>(posed - *taken).count() - (r ? r->wait_ms : 0.0);
      // The target bounds the waits: the kept pose's latency.
      realtime_wait.Record(latency_final_ms.back(), busy,
                           std::chrono::duration<double, std::milli>(first_posed.value_or(posed) - *taken).count());
    }
    for (const MapSet::Settled& st : settled) settle(st);
    if (map_set.current().NeedsNewMap() && i + 1 < end) {
      // Relocalisation keeps failing: the camera is somewhere new. Another map starts with the
      // next frames; this one is suspended, and resumes if the camera comes back (map_set.h).
      map_set.StartNewMap();
      progress.Event("frame " + std::to_string(i) + "  new map " + std::to_string(map_set.current_id()) +
                     " (relocalisation kept failing)");
    }
  };
  // Realtime: the waiting frames in order, each once the mapping side has settled, until `deadline`
  // (none: all of them, the run ended); one that waited too long at once (frame_backlog.h).
  FrameBacklog backlog;
  // A latency target bounds the kept pose's latency instead: no frame waits in the backlog.
  const bool use_backlog = std::isinf(options.realtime_latency_target_ms);
  const auto drain = [&](std::optional<std::chrono::steady_clock::time_point> deadline) {
    while (!backlog.frames.empty()) {
      const auto now = std::chrono::steady_clock::now();
      if (deadline && now >= *deadline) return;
      const WaitingFrame& w = backlog.frames.front();
      const bool overdue = std::chrono::duration<double, std::milli>(now - w.released).count() > FrameBacklog::kMaxWaitMs;
      if (!overdue && !map_set.current().WaitSettled(deadline.value_or(now + std::chrono::hours(1)))) return;
      backlog.overdue += overdue;
      take(w.index, w.image, w.released, w.taken, deadline, w.first_posed);
      backlog.frames.pop_front();
    }
  };
  for (int i = options.start; i < end; ++i) {
    interrupt_signal = InterruptSignal();
    if (interrupt_signal != 0) break;
    auto released = std::chrono::steady_clock::now();
    std::optional<std::chrono::steady_clock::time_point> taken;
    if (options.pace == Pace::kRealtime) {
      // Frames that arrived while tracking was busy: only the newest is kept, as a camera driver
      // with a one-frame buffer does.
      int newest = i;
      while (newest + 1 < end && release(newest + 1) <= released) ++newest;
      dropped += newest - i;
      i = newest;
      if (release(i) > released) std::this_thread::sleep_until(release(i));
      released = release(i);
      taken = std::chrono::steady_clock::now();  // Not before its release (slept until then).
    }
    if (!reader) prefetch.Reading(i);
    const FrameOrError frame = reader ? reader->Take(i) : TryReadFrame(dataset, undistorter, i);
    last_frame = i;
    if (frame.size_mismatch && !any_frame_used) {
      // The first frame that decodes has another size than the calibration: the calibration does
      // not belong to the recording, and no frame would be used.
      const std::string calibration =
          dataset.calibration_file.empty() ? dataset.root.string() : dataset.calibration_file.string();
      throw InputError(calibration + ": the calibration does not fit the recording: " + frame.error);
    }
    if (!frame.error.empty()) {
      // A bad file in a recording costs its frame, not the run.
      progress.Event("dsm: warning: " + frame.error + "; frame " + std::to_string(i) + " skipped", stderr);
      skipped.push_back(i);
      if (debug) debug->AddSkipped(i, map_set.current_id(), frame.error);
      continue;
    }
    any_frame_used = true;
    if (reader) released = std::chrono::steady_clock::now();
    if (!taken) {
      take(i, frame.image, released, std::nullopt, std::nullopt, std::nullopt);
      continue;
    }
    const auto deadline = realtime_wait.Deadline(released, i + 1 < end ? std::optional(release(i + 1)) : std::nullopt,
                                                 i + 2 < end ? std::optional(release(i + 2)) : std::nullopt);
    if (backlog.frames.empty() && (!use_backlog || map_set.current().WaitSettled(std::chrono::steady_clock::now()))) {
      take(i, frame.image, released, taken, deadline, std::nullopt);
      continue;
    }
    first_posed.reset();
    map_set.current().Preview(i, frame.image, dataset.frames[i].exposure_ms);
    backlog.frames.push_back({i, frame.image, released, *taken, first_posed});
    ++backlog.deferred;
    backlog.max_size = std::max(backlog.max_size, backlog.frames.size());
    // No later than the next frame's release either: its first pose (Preview) comes first.
    drain(i + 1 < end ? std::min(deadline, release(i + 1)) : deadline);
  }
  drain(std::nullopt);
  for (const MapSet::Settled& st : map_set.Flush()) settle(st);
  progress.Finish();
  map_set.current().Finish();
  if (live) live->Finish(map_set.current(), per_frame);

  // Speed against the recording: the frames' time span (one frame interval per frame) over the
  // time spent reading and processing them (mapping included); > 1 is faster than real time.
  const double process_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - process0).count();
  const int processed = last_frame + 1 - options.start;  // Frames read or skipped.
  const double recording_s = RecordingSpan(dataset, options.start, last_frame);
  const double fps = processed / process_s, realtime_factor = recording_s / process_s;
  map_set.Close();
  std::vector<MapRun> maps;
  for (std::optional<MapRun>& m : ended) maps.push_back(std::move(*m));
  const SystemStats s = Combined(maps);
  int map_points = 0;
  for (const MapRun& m : maps) map_points += m.map_points;
  RunSummary summary;
  nlohmann::json per_keyframe = nlohmann::json::array(), created = nlohmann::json::array();
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
    created.push_back(k.points_created);
  }
  summary.stats = {
      {"dataset", dataset.root.string()},
      {"camera", CameraJson(undistorter.output())},
      {"mode", MapModeName(options.system.mode)},
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
      {"per_keyframe", per_keyframe},
      {"per_frame", per_frame},
      {"timing_ms", {{"tracking", TimingStats(s.tracking_ms)}, {"tracing", TimingStats(s.tracing_ms)},
                     {"mapping", TimingStats(s.mapping_ms)}, {"pba", TimingStats(s.pba_ms)},
                     {"young_map_ba", TimingStats(s.young_map_ba_ms)}, {"loop_ba", TimingStats(s.loop_ba_ms)}}},
  };
  if (s.global_ba_ms >= 0.0) summary.stats["timing_ms"]["global_ba"] = s.global_ba_ms;
  summary.stats["pace"] = PaceName(options.pace);
  summary.stats["frames_dropped"] = dropped;
  summary.stats["frames_skipped"] = skipped.size();
  summary.stats["skipped_frames"] = skipped;
  summary.stats["interrupted"] = interrupt_signal != 0;
  summary.interrupt_signal = interrupt_signal;
  summary.stats["latency_ms"] = LatencyStats(latency_ms);
  summary.stats["latency_final_ms"] = LatencyStats(latency_final_ms);
  summary.stats["keyframe_queue_max"] = s.keyframe_queue_max;
  summary.stats["keyframe_waits"] = s.keyframe_waits;
  summary.stats["keyframe_wait_timeouts"] = s.keyframe_wait_timeouts;
  summary.stats["keyframe_retracks"] = s.keyframe_retracks;
  summary.stats["adjustments_yielded"] = s.adjustments_yielded;
  summary.stats["traces_skipped"] = s.traces_skipped;
  summary.stats["brightness_holds"] = s.brightness_holds;
  summary.stats["frames_posed_before_wait"] = posed_before_wait;
  summary.stats["frames_deferred"] = backlog.deferred;
  summary.stats["frames_overdue"] = backlog.overdue;
  summary.stats["backlog_max"] = backlog.max_size;
  summary.stats["pyramids_rebuilt"] = s.pyramids_rebuilt;
  // Keyframe culling: the keyframes the maps keep (made, less those culled) and what became of the
  // culled ones' points.
  summary.stats["keyframes_culled"] = s.keyframes_culled;
  summary.stats["keyframes_kept"] = s.keyframes - s.keyframes_culled;
  summary.stats["points_rehosted"] = s.points_rehosted;
  summary.stats["points_dropped"] = s.points_dropped;
  summary.stats["pyramids_loaded_max"] = s.pyramids_loaded_max;
  // Loop closure: places recognised, and the loops closed with their corrections.
  summary.stats["loops_detected"] = s.loops_detected;
  summary.stats["loops_closed"] = LoopsClosedJson(s);
  summary.stats["relocalised"] = RelocalisedJson(s);
  summary.stats["maps_merged"] = MapsMergedJson(s);
  summary.stats["processing_s"] = process_s;
  summary.stats["frames_per_second"] = fps;
  if (recording_s > 0.0) {
    summary.stats["recording_s"] = recording_s;
    summary.stats["realtime_factor"] = realtime_factor;
  }
  char line[512];
  std::snprintf(line, sizeof(line), "%d/%d frames tracked, %d keyframes, %d points, ", s.frames_tracked, s.frames,
                s.keyframes, map_points);
  summary.line = line;
  // A run that went on in a loaded map started none of its own.
  if (s.initialized_at_frame >= 0 || map_loaded.is_null())
    summary.line += "initialised at frame " + std::to_string(s.initialized_at_frame) + ", ";
  std::snprintf(line, sizeof(line), "%.1f fps", fps);
  summary.line += line;

  if (recording_s > 0.0) {
    std::snprintf(line, sizeof(line), " (%.2fx real time)", realtime_factor);
    summary.line += line;
  }
  if (s.frames_lost > 0) {
    std::snprintf(line, sizeof(line), ", %d lost (%zu episodes, %d relocalised)", s.frames_lost, s.lost_episodes.size(),
                  s.relocalisations);
    summary.line += line;
  }
  // Maps counted: those that took part (a new map that never started while the camera
  // relocalised in a loaded one does not).
  // Maps merged into another count with it.
  const size_t maps_made = std::count_if(maps.begin(), maps.end(), [](const MapRun& m) {
    return m.merged_into < 0 && (m.stats.keyframes > 0 || m.loaded_keyframes > 0);
  });
  if (maps_made > 1) summary.line += ", " + std::to_string(maps_made) + " maps";
  if (!s.maps_merged.empty()) summary.line += ", " + std::to_string(s.maps_merged.size()) + " merged";
  nlohmann::json map_list = nlohmann::json::array();
  for (size_t k = 0; k < maps.size(); ++k) {
    MapRun& m = maps[k];
    std::string map_line;
    EvaluateMap(dataset, &m, &map_line);
    if (k == 0) {
      summary.eval = m.eval;
      summary.line += map_line;
    } else if (!map_line.empty()) {
      summary.line += "; map " + std::to_string(k) + map_line;
    }
    if (m.merged_into >= 0) {
      map_list.push_back({{"dir", nullptr}, {"merged_into", m.merged_into}, {"frames_tracked", m.stats.frames_tracked},
                          {"keyframes", m.stats.keyframes}, {"initialized_at_frame", m.stats.initialized_at_frame}});
      continue;
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
    map_list.push_back(j);
  }
  summary.stats["maps"] = map_list;
  if (!map_loaded.is_null()) {
    summary.stats["map_loaded"] = map_loaded;
    summary.stats["relocalised_in_loaded_map_at_frame"] =
        relocalised_in_loaded_at >= 0 ? nlohmann::json(relocalised_in_loaded_at) : nlohmann::json(nullptr);
    // What this run added to the loaded maps (a new map that started meanwhile has its own row in
    // `maps`).
    // Localising, they are temporary: those retired are gone again, the rest go with the run.
    int keyframes_added = 0, points_added = 0, retired = 0;
    for (const MapRun& m : maps) {
      if (m.loaded_keyframes == 0) continue;
      keyframes_added += m.stats.keyframes;
      points_added += m.stats.points_created;
      retired += m.retired_keyframes;
    }
    summary.stats["keyframes_added"] = keyframes_added;
    summary.stats["points_added"] = points_added;
    summary.stats["localize"] = options.localize;
    if (options.localize) summary.stats["keyframes_retired"] = retired;
    summary.line += relocalised_in_loaded_at >= 0
                        ? "; relocalised in the loaded map at frame " + std::to_string(relocalised_in_loaded_at)
                        : "; never relocalised in the loaded map";
  }
  summary.stats["peak_rss_mb"] = PeakRssMb();
  // The map file: every map that has keyframes, in the order the run made them. A failure to write
  // it is reported after the other outputs are written.
  std::string save_error;
  if (!options.save_map.empty()) {
    MapFile file;
    file.created_by = std::string("dsm ") + kVersion;
    file.camera = undistorter.output();
    // Localising, the maps are the loaded ones, as the options of their own run made them.
    file.options = options.localize ? loaded_options : OptionsYaml(options.system);
    int keyframes = 0, points = 0;
    for (std::optional<StoredMap>& m : stored) {
      if (!m || m->map.NumKeyframes() == 0) continue;
      keyframes += m->map.NumKeyframes();
      points += m->map.NumLivePoints();
      file.maps.push_back(std::move(*m));
    }
    try {
      WriteMapFile(options.save_map, file);
      summary.stats["map_saved"] = {{"file", options.save_map.string()},
                                    {"maps", file.maps.size()},
                                    {"keyframes", keyframes},
                                    {"points", points}};
    } catch (const InputError& e) {
      save_error = e.what();
    }
  }
  summary.stats["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  WriteJson(out_dir / "stats.json", summary.stats);
  if (options.write_report) WriteReport(out_dir);
  if (!save_error.empty()) throw InputError(save_error + " (the run's other outputs are written)");
  return summary;
}

}  // namespace dsm
