// SPDX-License-Identifier: MIT
// dsm run --view: the report page served on localhost while the run goes on (report/live_server.h).
// After each frame the run's thread hands its report here; at most every `interval_s` (and at the
// end) a document in the report's layout (report/report.h) is published: the map as the tracking
// side last took it over (System::TrackedMapSnapshot, so it is safe in every pace), the camera of
// the last tracked frame ("current": {p, q}), and the counts and tracking times so far. The frame
// counts and lost episodes are the system's own (SystemStats fields the tracking side keeps: safe
// to read between Process calls), so they are those of the current map.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/io/dataset.h"
#include "dsm/report/live_server.h"
#include "dsm/run/progress.h"
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
  // Blocks until a browser has connected or `seconds` have passed; whether one has.
  bool WaitForBrowser(double seconds) const;

  // After each frame: `progress` as the console shows it, the run's per-frame tracking times
  // ({frame, tracking_ms}), `map_index`: which map of the run the system is.
  void Frame(const System& system, const ProgressState& progress, const nlohmann::json& per_frame, int map_index);
  // Publishes the last state now (the run has ended; call System::Finish first).
  void Finish(const System& system, const nlohmann::json& per_frame);

 private:
  void Publish(const System& system, const nlohmann::json& per_frame);

  const Dataset& dataset_;
  Context context_;
  std::unique_ptr<LiveServer> server_;
  ProgressState progress_;
  int map_index_ = 0;
  double last_publish_s_ = -1e9;
};

}  // namespace dsm
