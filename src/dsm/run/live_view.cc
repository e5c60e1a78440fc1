// SPDX-License-Identifier: MIT
#include "dsm/run/live_view.h"

#include <chrono>
#include <thread>

#include "dsm/report/report.h"

namespace dsm {

using nlohmann::json;

LiveView::LiveView(int port, const Dataset& dataset, Context context) : dataset_(dataset), context_(std::move(context)) {
  const json empty = {{"title", context_.title}, {"camera", context_.camera},
                      {"summary", {{"frames", 0}, {"frames_tracked", 0}, {"keyframes", 0}, {"map_points", 0},
                                   {"mode", context_.mode}, {"pace", context_.pace}, {"state", "starting"}}},
                      {"maps", json::array()}, {"errors", json::array()}, {"lost_episodes", json::array()}};
  server_ = std::make_unique<LiveServer>(port, ReportPage(empty, /*live=*/true));
}

bool LiveView::WaitForBrowser(double seconds) const {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (server_->NumConnections() == 0) {
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

void LiveView::Frame(const System& system, const ProgressState& progress, const json& per_frame, int map_index) {
  progress_ = progress;
  map_index_ = map_index;
  if (progress.elapsed_s - last_publish_s_ < context_.interval_s) return;
  last_publish_s_ = progress.elapsed_s;
  Publish(system, per_frame);
}

void LiveView::Finish(const System& system, const json& per_frame) {
  progress_.state = "finished";
  Publish(system, per_frame);
}

void LiveView::Publish(const System& system, const json& per_frame) {
  const std::shared_ptr<const MapSnapshot> snapshot = system.TrackedMapSnapshot();
  json map = {{"dir", map_index_ == 0 ? "." : "map_" + std::to_string(map_index_)},
              {"keyframes", json::array()}, {"covisibility", json::array()}, {"groundtruth", json::array()}};
  std::vector<float> xyz;
  std::vector<uint8_t> grey;
  if (snapshot) {
    for (const LivePoint& p : snapshot->points) {
      xyz.insert(xyz.end(), p.world.data(), p.world.data() + 3);
      grey.push_back(p.grey);
    }
    const int64_t t0 = dataset_.frames.front().t_ns;
    for (size_t k = 0; k < snapshot->world_from_cam.size(); ++k) {
      const int frame = snapshot->keyframe_frames[k];
      map["keyframes"].push_back(KeyframeJson(static_cast<int>(k), frame, 1e-9 * (dataset_.frames[frame].t_ns - t0),
                                              snapshot->world_from_cam[k]));
    }
    for (const auto& [a, b] : snapshot->covisibility) map["covisibility"].push_back({a, b});
  }
  map["points"] = PointsJson(xyz, grey);
  const SystemStats& stats = system.stats();
  const System::MapSize size = system.TrackedMapSize();
  json summary = {{"frames", stats.frames}, {"frames_tracked", stats.frames_tracked}, {"keyframes", size.keyframes},
                  {"map_points", size.points}, {"mode", context_.mode}, {"pace", context_.pace},
                  {"frames_lost", stats.frames_lost}, {"relocalisations", stats.relocalisations},
                  {"state", progress_.state}};
  if (progress_.elapsed_s > 0.0) {
    summary["frames_per_second"] = progress_.done / progress_.elapsed_s;
    if (progress_.recording_s > 0.0) summary["realtime_factor"] = progress_.recording_s / progress_.elapsed_s;
  }
  json document = {{"title", context_.title}, {"camera", context_.camera}, {"summary", summary},
                   {"maps", json::array({map})}, {"errors", json::array()}, {"per_frame", per_frame},
                   {"lost_episodes", stats.lost_episodes}};
  if (const std::optional<SE3d> pose = system.LastFramePose()) {
    const json kf = KeyframeJson(-1, -1, 0.0, *pose);
    document["current"] = {{"p", kf["p"]}, {"q", kf["q"]}};
  }
  server_->Publish(document.dump());
}

}  // namespace dsm
