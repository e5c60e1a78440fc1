// SPDX-License-Identifier: MIT
// dsm run --view: the report page served on localhost while the run goes on (report/live_server.h).
// After each frame the run's thread hands its report here; at most every `interval_s` (and at the
// end) a document in the report's layout (report/report.h) is published: the map as the tracking
// side last took it over (System::TrackedMapSnapshot, so it is safe in every pace), the camera of
// the last tracked frame ("current": {p, q}), and the run's counts and tracking times so far.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/io/dataset.h"
#include "dsm/report/live_server.h"
#include "dsm/system/system.h"

namespace dsm {

class LiveView {
 public:
  struct Context {
    std::string title, mode, pace;
    nlohmann::json camera;
    double interval_s = 0.25;
  };
  // Throws InputError when the port cannot be listened on.
  LiveView(int port, const Dataset& dataset, Context context);
  int port() const { return server_->port(); }

  // Frame `index` was processed (map_index: which map of the run it went to).
  void Frame(const System& system, const FrameReport& report, int index, int map_index, double elapsed_s,
             double recording_s);
  // Publishes the last state now (the run has ended; call System::Finish first).
  void Finish(const System& system);

 private:
  void Publish(const System& system);

  const Dataset& dataset_;
  Context context_;
  std::unique_ptr<LiveServer> server_;
  nlohmann::json per_frame_ = {{"frame", nlohmann::json::array()}, {"tracking_ms", nlohmann::json::array()}};
  nlohmann::json summary_;
  std::vector<std::pair<int, int>> lost_episodes_;
  int map_index_ = 0;
  double last_publish_s_ = -1e9;
};

}  // namespace dsm
