// SPDX-License-Identifier: MIT
#include "dsm/run/live_view.h"

#include "dsm/report/report.h"

namespace dsm {

using nlohmann::json;

LiveView::LiveView(int port, const Dataset& dataset, Context context) : dataset_(dataset), context_(std::move(context)) {
  const json empty = {{"title", context_.title}, {"camera", context_.camera},
                      {"summary", {{"frames", 0}, {"frames_tracked", 0}, {"keyframes", 0}, {"map_points", 0},
                                   {"mode", context_.mode}, {"pace", context_.pace}, {"state", "starting"}}},
                      {"maps", json::array()}, {"errors", json::array()}, {"lost_episodes", json::array()}};
  server_ = std::make_unique<LiveServer>(port, ReportPage(empty, /*live=*/true));
  summary_ = empty["summary"];
  summary_["frames_lost"] = summary_["relocalisations"] = 0;
}

void LiveView::Frame(const System& system, const FrameReport& report, int index, int map_index, double elapsed_s,
                     double recording_s) {
  per_frame_["frame"].push_back(index);
  per_frame_["tracking_ms"].push_back(report.tracking_ms);
  map_index_ = map_index;
  const bool lost = report.status == TrackingStatus::kLost;
  if (lost) {
    if (!lost_episodes_.empty() && lost_episodes_.back().second + 1 >= index) {
      lost_episodes_.back().second = index;
    } else {
      lost_episodes_.push_back({index, index});
    }
  }
  json& s = summary_;
  s["frames"] = s["frames"].get<int>() + 1;
  s["frames_tracked"] = s["frames_tracked"].get<int>() + (report.status == TrackingStatus::kOk);
  s["frames_lost"] = s["frames_lost"].get<int>() + lost;
  s["relocalisations"] = s["relocalisations"].get<int>() + report.relocalised;
  s["frames_per_second"] = elapsed_s > 0.0 ? s["frames"].get<int>() / elapsed_s : 0.0;
  if (recording_s > 0.0 && elapsed_s > 0.0) s["realtime_factor"] = recording_s / elapsed_s;
  s["state"] = report.status == TrackingStatus::kOk ? "tracking" : lost ? "lost" : "initialising";
  if (elapsed_s - last_publish_s_ < context_.interval_s) return;
  last_publish_s_ = elapsed_s;
  Publish(system);
}

void LiveView::Finish(const System& system) {
  summary_["state"] = "finished";
  // The frames before the map started count as tracked once it has (System::Finish placed them).
  summary_["frames_tracked"] = system.stats().frames_tracked;
  Publish(system);
}

void LiveView::Publish(const System& system) {
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
  json document = {{"title", context_.title}, {"camera", context_.camera}, {"maps", json::array({map})},
                   {"errors", json::array()}, {"per_frame", per_frame_}, {"lost_episodes", lost_episodes_}};
  json summary = summary_;
  const System::MapSize size = system.TrackedMapSize();
  summary["keyframes"] = size.keyframes;
  summary["map_points"] = size.points;
  document["summary"] = summary;
  if (const std::optional<SE3d> pose = system.LastFramePose()) {
    const json kf = KeyframeJson(-1, -1, 0.0, *pose);
    document["current"] = {{"p", kf["p"]}, {"q", kf["q"]}};
  }
  server_->Publish(document.dump());
}

}  // namespace dsm
