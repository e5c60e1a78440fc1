// SPDX-License-Identifier: MIT
#include "dsm/run/dataset_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>

#include "dsm/config/option_registry.h"
#include "dsm/report/report.h"
#include "dsm/run/mcap_export.h"
#include "dsm/run/interrupt.h"
#include "dsm/util/check.h"
#include "dsm/util/version.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

// The end of the frames the run takes, once the options are checked against the dataset and
// the output folder exists.
int CheckedEnd(const Dataset& dataset, const RunOptions& options, const fs::path& out_dir, bool live) {
  options.system.Validate();
  if (live) {
    if (options.pace != Pace::kRealtime) throw InputError("a live camera runs in the realtime pace");
    if (options.start != 0 || options.end >= 0) throw InputError("--start and --end select frames of a recording, not of a live camera");
  }
  const int n = live ? std::numeric_limits<int>::max() : static_cast<int>(dataset.size());
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
  return end;
}

std::unique_ptr<tbb::global_control> Workers(int workers) {
  if (workers <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, workers);
}

// How the pace, the viewer and the camera's calibration have the systems run.
SystemSetup PacedSetup(const RunOptions& options, const Dataset& dataset) {
  SystemSetup s;
  s.threaded = options.pace != Pace::kSequential;
  s.wait_for_mapping = options.pace != Pace::kRealtime;
  s.yield_adjustments = options.pace == Pace::kRealtime;
  s.keyframe_features = options.pace == Pace::kRealtime;
  s.skip_traces_while_mapping = options.pace == Pace::kFree;
  s.map_snapshots = options.view_port >= 0;
  s.line_delay_s = dataset.line_delay_us * 1e-6;
  return s;
}

// The most resident memory the process has had so far.
double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes.
}

}  // namespace

DatasetRun::DatasetRun(const Dataset& dataset, const RunOptions& options, fs::path out_dir, LiveCamera* camera)
    : dataset_(dataset),
      options_(options),
      camera_(camera),
      out_dir_(std::move(out_dir)),
      end_(CheckedEnd(dataset, options, out_dir_, camera != nullptr)),
      workers_(Workers(options.workers)),
      setup_(PacedSetup(options, dataset)),
      undistorter_(FrameUndistorter(dataset, options.system)),
      progress_(options.quiet ? nullptr : stdout, isatty(fileno(stdout)) != 0, options.progress_interval_s),
      realtime_wait_(options.realtime_latency_target_ms),
      use_backlog_(std::isinf(options.realtime_latency_target_ms)) {
  if (!options.debug_dir.empty()) debug_.emplace(options.debug_dir, dataset, undistorter_);
  if (options.view_port >= 0) {
    LiveView::Context context{ReportTitle(dataset.root), MapModeName(options.system.mode), PaceName(options.pace),
                              CameraJson(undistorter_.output())};
    live_.emplace(options.view_port, dataset, context);
    std::printf("view: http://127.0.0.1:%d/ (updated while the run goes on)\n", live_->port());
    std::fflush(stdout);
    if (options.view_wait_s > 0.0 && !live_->WaitForBrowser(options.view_wait_s)) {
      std::printf("view: no browser connected within %g s; the run goes on\n", options.view_wait_s);
      std::fflush(stdout);
    }
  }
  if (!options.save_map.empty() && fs::is_directory(options.save_map)) {
    throw InputError(options.save_map.string() + ": --save-map names a folder, not a file");
  }
  if (options.localize && options.load_map.empty()) throw InputError("--localize needs a map to localise in (--load-map)");
  // The maps of a map file are read before the run's clock starts (realtime: before the first
  // frame is released).
  std::vector<StoredMap> loaded;
  if (!options.load_map.empty()) {
    MapFile read = ReadMapFile(options.load_map);
    loaded_options_ = read.options;
    loaded = MapsToTakeUp(options.load_map, std::move(read), undistorter_.output());
  }
  maps_.emplace([this] { return MakeSystem(); },
                [this](int id, System& system, const Atlas::Spans& spans, int merged_into) {
                  EndMap(id, system, spans, merged_into);
                },
                std::move(loaded), options.localize ? System::LoadedMapUse::kLocalize : System::LoadedMapUse::kExtend);
  if (maps_->loaded_maps() > 0) {
    int keyframes = 0, points = 0;
    for (int id = 0; id < maps_->loaded_maps(); ++id) {
      keyframes += maps_->Find(id)->loaded_keyframes();
      points += maps_->Find(id)->loaded_points();
    }
    map_loaded_ = {{"file", options.load_map.string()}, {"maps", maps_->loaded_maps()}, {"keyframes", keyframes},
                   {"points", points}};
  }
  process0_ = Clock::now();
  // Free and sequential paces: frames read ahead on the reader's thread. Realtime: a frame is read
  // once released (a live camera cannot be read ahead).
  if (options.pace != Pace::kRealtime) {
    reader_.emplace(dataset, undistorter_, options.start, end_, 2);
  } else if (!camera) {
    prefetch_.emplace(dataset, end_);
  }
  shown_.total = camera ? 0 : end_ - options.start;
  fed_.last_frame = options.start - 1;
}

std::unique_ptr<System> DatasetRun::MakeSystem() {
  auto system = std::make_unique<System>(undistorter_.output(), options_.system, setup_);
  system->SetPoseListener([this](int, const SE3d&) {
    if (!first_posed_) first_posed_ = Clock::now();
  });
  return system;
}

void DatasetRun::EndMap(int id, System& system, const Atlas::Spans& spans, int merged_into) {
  if (ended_.size() <= static_cast<size_t>(id)) ended_.resize(id + 1);
  if (merged_into >= 0) {
    // Its keyframes, points and frames are the other map's now: only its counts stay.
    system.Finish();
    MapRun m;
    m.merged_into = merged_into;
    m.stats = system.stats();
    ended_[id] = std::move(m);
    return;
  }
  // A map saved for later sessions is adjusted whole first (System::TakeStoredMap): the
  // trajectories written are the map's as saved.
  const bool saved = !options_.save_map.empty() && maps_->SavedInMapFile(system);
  const fs::path dir = id == 0 ? out_dir_ : out_dir_ / ("map_" + std::to_string(id));
  ended_[id] = CloseMap(system, dir, spans, (options_.global_ba || saved) && !system.localizing(),
                        undistorter_.output(), options_.write_map,
                        options_.truth_ba && dataset_.HasGroundTruth() ? &dataset_.ground_truth : nullptr,
                        !options_.mcap.empty());
  if (saved) {
    if (stored_.size() <= static_cast<size_t>(id)) stored_.resize(id + 1);
    stored_[id] = system.TakeStoredMap();
  }
}

DatasetRun::TimePoint DatasetRun::ReleaseTime(int i) const {
  return process0_ + std::chrono::nanoseconds(dataset_.frames[i].t_ns - dataset_.frames[options_.start].t_ns);
}

std::optional<DatasetRun::TimePoint> DatasetRun::NextRelease(int k) const {
  if (camera_) return camera_->Expected(k);
  return k < end_ ? std::optional(ReleaseTime(k)) : std::nullopt;
}

void DatasetRun::Settle(const Atlas::Settled& s) {
  const FrameReport& r = s.report;
  const int i = r.index;
  if (debug_) debug_->AddFrame(r, s.map);
  if (debug_ && r.keyframe && s.map == 0) debug_->AddKeyframes(maps_->current());  // The first map's.
  // Events: tracking lost (once per episode), regained, and a map the camera came back to.
  // The first frame in a loaded map is told as such, and the next one, which confirms it, not again.
  int& in_loaded_at = fed_.relocalised_in_loaded_at;
  const bool first_in_loaded = r.status == TrackingStatus::kOk && s.map < maps_->loaded_maps() && in_loaded_at < 0;
  if (first_in_loaded) in_loaded_at = i;
  const bool confirms_first_in_loaded = r.resumed && s.map < maps_->loaded_maps() && i == in_loaded_at + 1;
  if (first_in_loaded) {
    progress_.Event("frame " + std::to_string(i) + "  relocalised in the loaded map " + std::to_string(s.map));
  } else if (r.resumed && !confirms_first_in_loaded) {
    progress_.Event("frame " + std::to_string(i) + "  back in map " + std::to_string(s.map) + " (relocalised)");
  } else if (r.relocalised || (r.status == TrackingStatus::kLost && last_status_ != TrackingStatus::kLost)) {
    progress_.Event("frame " + std::to_string(i) + "  " + (r.relocalised ? "relocalised" : "tracking lost") +
                    (r.reason.empty() ? "" : "  (" + r.reason + ")"));
  }
  last_status_ = r.status;
  fed_.per_frame["frame"].push_back(i);
  fed_.per_frame["tracking_ms"].push_back(r.tracking_ms);
  fed_.per_frame["wait_ms"].push_back(r.wait_ms);
  fed_.per_frame["tracking_rmse"].push_back(r.tracking_rmse);
  shown_.frame = i;
  shown_.done = i + 1 - options_.start;
  shown_.elapsed_s = std::chrono::duration<double>(Clock::now() - process0_).count();
  shown_.recording_s = RecordingSpan(dataset_, options_.start, i);
  const System::MapSize size = maps_->current().TrackedMapSize();
  shown_.keyframes = size.keyframes;
  shown_.points = size.points;
  shown_.state = r.status == TrackingStatus::kOk ? "tracking" : r.status == TrackingStatus::kLost ? "lost" : "initialising";
  progress_.Update(shown_);
  if (live_) live_->Frame(maps_->current(), shown_, fed_.per_frame, s.map);
}

void DatasetRun::Take(int i, const Image<float>& image, TimePoint released, std::optional<TimePoint> taken,
                      std::optional<TimePoint> wait_until, std::optional<TimePoint> first_pose) {
  first_posed_ = first_pose;
  const std::vector<Atlas::Settled> settled =
      maps_->Process(i, dataset_.frames[i].t_ns, image, dataset_.frames[i].exposure_ms, wait_until);
  const auto posed = Clock::now();
  using Ms = std::chrono::duration<double, std::milli>;
  fed_.latency_ms.push_back(Ms(first_posed_.value_or(posed) - released).count());
  fed_.latency_final_ms.push_back(Ms(posed - released).count());
  const FrameReport* r = nullptr;  // This frame's, when settled now.
  for (const Atlas::Settled& st : settled)
    if (st.report.index == i) r = &st.report;
  if (first_pose || (r && r->posed_before_wait)) ++fed_.posed_before_wait;
  if (taken) {
    const double busy = r && r->wait_end ? Ms(posed - *r->wait_end).count()
                                         : Ms(posed - *taken).count() - (r ? r->wait_ms : 0.0);
    // The target bounds the waits: the kept pose's latency.
    realtime_wait_.Record(fed_.latency_final_ms.back(), busy, Ms(first_posed_.value_or(posed) - *taken).count());
  }
  for (const Atlas::Settled& st : settled) Settle(st);
  if (maps_->current().NeedsNewMap() && i + 1 < end_) {
    // Relocalisation keeps failing: the camera is somewhere new. Another map starts with the
    // next frames; this one is suspended, and resumes if the camera comes back (atlas.h).
    maps_->StartNewMap();
    progress_.Event("frame " + std::to_string(i) + "  new map " + std::to_string(maps_->current_id()) +
                    " (relocalisation kept failing)");
  }
}

void DatasetRun::Drain(std::optional<TimePoint> deadline) {
  while (!backlog_.frames.empty()) {
    const auto now = Clock::now();
    if (deadline && now >= *deadline) return;
    const WaitingFrame& w = backlog_.frames.front();
    const bool overdue = std::chrono::duration<double, std::milli>(now - w.released).count() > FrameBacklog::kMaxWaitMs;
    if (!overdue && !maps_->current().WaitSettled(deadline.value_or(now + std::chrono::hours(1)))) return;
    backlog_.overdue += overdue;
    Take(w.index, w.image, w.released, w.taken, deadline, w.first_posed);
    backlog_.frames.pop_front();
  }
}

void DatasetRun::TakeReleased(int i, const Image<float>& image, TimePoint released, TimePoint taken) {
  const TimePoint deadline = realtime_wait_.Deadline(released, NextRelease(i + 1), NextRelease(i + 2));
  if (backlog_.frames.empty() && (!use_backlog_ || maps_->current().WaitSettled(Clock::now()))) {
    Take(i, image, released, taken, deadline, std::nullopt);
    return;
  }
  first_posed_.reset();
  maps_->current().Preview(i, image, dataset_.frames[i].exposure_ms);
  backlog_.frames.push_back({i, image, released, taken, first_posed_});
  ++backlog_.deferred;
  backlog_.max_size = std::max(backlog_.max_size, backlog_.frames.size());
  // No later than the next frame's release either: its first pose (Preview) comes first.
  const std::optional<TimePoint> next = NextRelease(i + 1);
  Drain(next ? std::min(deadline, *next) : deadline);
}

void DatasetRun::FeedLive() {
  const auto interrupted = [] { return InterruptSignal() != 0; };
  while (true) {
    LiveCamera::Frame frame = camera_->Take(interrupted);
    fed_.interrupt_signal = InterruptSignal();
    if (frame.status != LiveCamera::Status::kFrame) {
      live_end_ = std::move(frame);
      return;
    }
    if (fed_.interrupt_signal != 0) return;
    const int i = frame.index;
    fed_.dropped += i - (fed_.last_frame + 1);  // Captured while tracking was busy.
    fed_.last_frame = i;
    any_frame_used_ = true;
    TakeReleased(i, PrepareFrame(dataset_, undistorter_, frame.image), frame.captured, Clock::now());
  }
}

void DatasetRun::FeedFrames() {
  if (camera_) {
    FeedLive();
    return;
  }
  for (int i = options_.start; i < end_; ++i) {
    fed_.interrupt_signal = InterruptSignal();
    if (fed_.interrupt_signal != 0) break;
    auto released = Clock::now();
    std::optional<TimePoint> taken;
    if (options_.pace == Pace::kRealtime) {
      // Frames that arrived while tracking was busy: only the newest is kept, as a camera driver
      // with a one-frame buffer does.
      int newest = i;
      while (newest + 1 < end_ && ReleaseTime(newest + 1) <= released) ++newest;
      fed_.dropped += newest - i;
      i = newest;
      if (ReleaseTime(i) > released) std::this_thread::sleep_until(ReleaseTime(i));
      released = ReleaseTime(i);
      taken = Clock::now();  // Not before its release (slept until then).
    }
    if (prefetch_) prefetch_->Reading(i);
    const FrameOrError frame = reader_ ? reader_->Take(i) : TryReadFrame(dataset_, undistorter_, i);
    fed_.last_frame = i;
    if (frame.size_mismatch && !any_frame_used_) {
      // The first frame that decodes has another size than the calibration: the calibration does
      // not belong to the recording, and no frame would be used.
      const std::string calibration =
          dataset_.calibration_file.empty() ? dataset_.root.string() : dataset_.calibration_file.string();
      throw InputError(calibration + ": the calibration does not fit the recording: " + frame.error);
    }
    if (frame.damaged) {
      fed_.damaged_input = frame.error;
      break;
    }
    if (!frame.error.empty()) {
      // A bad file in a recording costs its frame, not the run.
      progress_.Event("dsm: warning: " + frame.error + "; frame " + std::to_string(i) + " skipped", stderr);
      fed_.skipped.push_back(i);
      if (debug_) debug_->AddSkipped(i, maps_->current_id(), frame.error);
      continue;
    }
    any_frame_used_ = true;
    if (taken) {
      TakeReleased(i, frame.image, released, *taken);
    } else {
      Take(i, frame.image, Clock::now(), std::nullopt, std::nullopt, std::nullopt);
    }
  }
}

void DatasetRun::WriteMcap(const std::vector<MapRun>& maps, RunSummary* summary) {
  std::vector<McapMap> written;
  for (size_t id = 0; id < maps.size(); ++id) {
    const MapRun& m = maps[id];
    if (m.merged_into >= 0) continue;
    written.push_back({static_cast<int>(id), m.frames, m.keyframes, m.points, m.keyframe_images});
  }
  nlohmann::json topics = nlohmann::json::object();
  for (const auto& [topic, count] : WriteRunMcap(options_.mcap, written, undistorter_.output())) topics[topic] = count;
  summary->stats["mcap"] = {{"file", options_.mcap.string()}, {"messages", topics}};
}

std::string DatasetRun::SaveMapFile(RunSummary* summary) {
  // Every map that has keyframes, in the order the run made them.
  MapFile file;
  file.created_by = std::string("dsm ") + kVersion;
  file.camera = undistorter_.output();
  // Localising, the maps are the loaded ones, as the options of their own run made them.
  file.options = options_.localize ? loaded_options_ : OptionsYaml(options_.system);
  int keyframes = 0, points = 0;
  for (std::optional<StoredMap>& m : stored_) {
    if (!m || m->map.NumKeyframes() == 0) continue;
    keyframes += m->map.NumKeyframes();
    points += m->map.NumLivePoints();
    file.maps.push_back(std::move(*m));
  }
  try {
    WriteMapFile(options_.save_map, file);
    summary->stats["map_saved"] = {
        {"file", options_.save_map.string()}, {"maps", file.maps.size()}, {"keyframes", keyframes}, {"points", points}};
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

RunSummary DatasetRun::Finish() {
  if (camera_) camera_->Stop();
  Drain(std::nullopt);
  for (const Atlas::Settled& st : maps_->Flush()) Settle(st);
  progress_.Finish();
  maps_->current().Finish();
  if (live_) live_->Finish(maps_->current(), fed_.per_frame);
  fed_.process_s = std::chrono::duration<double>(Clock::now() - process0_).count();
  maps_->Close();
  std::vector<MapRun> maps;
  for (std::optional<MapRun>& m : ended_) maps.push_back(std::move(*m));
  RunSummary summary =
      SummariseRun(dataset_, options_, undistorter_.output(), fed_, backlog_, &maps, map_loaded_, out_dir_);
  summary.stats["peak_rss_mb"] = PeakRssMb();
  summary.stats.update(extra_stats_);
  if (camera_) {
    static const char* kEnds[] = {"frame", "ended", "stalled", "frame size"};
    summary.stats["live"] = {{"source", dataset_.root.string()},
                             {"frames_captured", camera_->captured()},
                             {"ended", fed_.interrupt_signal != 0 ? "interrupted" : kEnds[static_cast<int>(live_end_.status)]},
                             {"message", live_end_.message}};
  }
  // A failure to write the map file is reported after the other outputs are written.
  const std::string save_error = options_.save_map.empty() ? "" : SaveMapFile(&summary);
  if (!options_.mcap.empty()) WriteMcap(maps, &summary);
  summary.stats["wall_s"] = std::chrono::duration<double>(Clock::now() - wall0_).count();
  WriteJson(out_dir_ / "stats.json", summary.stats);
  if (options_.write_report) WriteReport(out_dir_);
  if (!save_error.empty()) throw InputError(save_error + " (the run's other outputs are written)");
  if (!fed_.damaged_input.empty()) {
    throw InputError(fed_.damaged_input + " (the run stopped at frame " + std::to_string(fed_.last_frame) +
                     "; its outputs up to there are written)");
  }
  return summary;
}

}  // namespace dsm
