// SPDX-License-Identifier: MIT
// One run over a dataset (RunDataset, run.h) and the state it keeps between frames.
//
// FeedFrames takes the frames in order. Each is released (realtime: at its recorded time; the
// frames that came while tracking was busy are dropped, as by a camera driver with a one-frame
// buffer), read (free, sequential: ahead, on the reader's thread), handed to the maps (atlas.h)
// and settled: its events, diagnostics, progress and live view. In the realtime pace a frame that
// comes while the mapping side is busy is told a first pose at once and waits in the backlog
// (frame_backlog.h), or waits for the keyframe being mapped up to a latency target
// (realtime_wait.h). Finish closes every map (map_run.h) and writes stats.json (run_stats.h), the
// report and the map file.
//
// Everything here is the caller's thread's; the maps' mapping sides run on their own.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "dsm/geometry/undistorter.h"
#include "dsm/io/dataset.h"
#include "dsm/io/live_camera.h"
#include "dsm/mapfile/map_file.h"
#include "dsm/run/debug_writer.h"
#include "dsm/run/frame_backlog.h"
#include "dsm/run/frame_reader.h"
#include "dsm/run/live_view.h"
#include "dsm/run/map_run.h"
#include "dsm/system/atlas.h"
#include "dsm/run/progress.h"
#include "dsm/run/realtime_wait.h"
#include "dsm/run/run.h"
#include "dsm/run/run_stats.h"

namespace dsm {

class DatasetRun {
 public:
  // Checks the options against the dataset (InputError), creates the output folder, opens the
  // live view and takes up the maps of RunOptions::load_map. The run's clock starts here.
  // With a live camera (`dataset` its dataset()), the frames are the camera's as it captures
  // them, in the realtime pace: the recorded frames' release times are their capture times.
  DatasetRun(const Dataset& dataset, const RunOptions& options, std::filesystem::path out_dir,
             LiveCamera* camera = nullptr);
  DatasetRun(const DatasetRun&) = delete;  // Its systems' pose listeners point at it.
  DatasetRun& operator=(const DatasetRun&) = delete;

  // Feeds frames start .. end - 1 in the pace's way (a live camera's until its stream ends);
  // stops early after SIGINT / SIGTERM.
  void FeedFrames();
  // A live camera's: how its stream ended (LiveCamera::Take's last answer).
  const LiveCamera::Frame& live_end() const { return live_end_; }
  // Ends the maps, writes every output and returns the summary; InputError after the other
  // outputs are written when the map file cannot be.
  RunSummary Finish();
  // An entry of stats.json beside the run's own (set before Finish).
  void AddStats(const std::string& key, nlohmann::json value) { extra_stats_[key] = std::move(value); }

 private:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;

  std::unique_ptr<System> MakeSystem();
  // Atlas's Closer: writes map `id`'s outputs (map_run.h) and keeps what --save-map stores.
  void EndMap(int id, System& system, const Atlas::Spans& spans, int merged_into);
  // Realtime: when frame i is released, as a camera would deliver it.
  TimePoint ReleaseTime(int i) const;
  // Realtime: when frame k after the current one is released (a live camera's: expected); none
  // past the end.
  std::optional<TimePoint> NextRelease(int k) const;
  // A live camera's frames, each taken when captured (the camera keeps the newest).
  void FeedLive();
  // Frame i handed to the maps, its latencies and events; `first_pose` told before (Preview).
  void Take(int i, const Image<float>& image, TimePoint released, std::optional<TimePoint> taken,
            std::optional<TimePoint> wait_until, std::optional<TimePoint> first_pose);
  // A frame settled in map `s.map`: its events, diagnostics and progress.
  void Settle(const Atlas::Settled& s);
  // Realtime: the waiting frames in order, each once the mapping side has settled, until
  // `deadline` (none: all of them, the run ended); one that waited too long at once.
  void Drain(std::optional<TimePoint> deadline);
  // Realtime: the frame `i` is one of the frames taken with a backlog or a latency target.
  void TakeReleased(int i, const Image<float>& image, TimePoint released, TimePoint taken);
  // The map file of RunOptions::save_map; the error, if it cannot be written.
  std::string SaveMapFile(RunSummary* summary);
  // Writes RunOptions::mcap from the maps that ended (stats.json "mcap": the file, the messages per
  // topic).
  void WriteMcap(const std::vector<MapRun>& maps, RunSummary* summary);

  const Dataset& dataset_;
  const RunOptions& options_;
  LiveCamera* const camera_;  // Null: the dataset's recorded frames.
  LiveCamera::Frame live_end_;
  const std::filesystem::path out_dir_;
  const TimePoint wall0_ = Clock::now();
  const int end_;  // One past the last frame.
  const std::unique_ptr<tbb::global_control> workers_;  // RunOptions::workers, when set.
  const SystemSetup setup_;  // How the pace, the viewer and the calibration have the systems run.
  const Undistorter undistorter_;
  std::optional<DebugWriter> debug_;
  std::optional<LiveView> live_;

  std::optional<TimePoint> first_posed_;  // The current frame's (System::SetPoseListener).
  std::vector<std::optional<MapRun>> ended_;      // By map id.
  std::vector<std::optional<StoredMap>> stored_;  // By map id, with --save-map.
  std::string loaded_options_;  // The options that made the loaded maps.
  nlohmann::json map_loaded_;  // stats.json's "map_loaded" (null: no map file).
  std::optional<Atlas> maps_;

  TimePoint process0_;  // The first frame's release.
  std::optional<FrameReader> reader_;  // Free and sequential paces.
  std::optional<FramePrefetch> prefetch_;  // Realtime: the reader's, on this thread.
  bool any_frame_used_ = false;  // A frame of the calibration's size was read.
  Progress progress_;
  ProgressState shown_;
  TrackingStatus last_status_ = TrackingStatus::kInitializing;
  RealtimeWait realtime_wait_;
  FrameBacklog backlog_;
  bool use_backlog_ = true;  // No latency target: frames wait in the backlog, not for a keyframe.
  FeedRecord fed_;
  nlohmann::json extra_stats_ = nlohmann::json::object();
};

}  // namespace dsm
