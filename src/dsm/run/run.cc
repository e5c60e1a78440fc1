// SPDX-License-Identifier: MIT
#include "dsm/run/run.h"

#include "dsm/run/dataset_run.h"
#include "dsm/util/check.h"

namespace dsm {

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

RunSummary RunDataset(const Dataset& dataset, const RunOptions& options, const std::filesystem::path& out_dir) {
  DatasetRun run(dataset, options, out_dir);
  run.FeedFrames();
  return run.Finish();
}

RunSummary RunCamera(LiveCamera& camera, const RunOptions& options, const std::filesystem::path& out_dir) {
  DatasetRun run(camera.dataset(), options, out_dir, &camera);
  run.FeedFrames();
  RunSummary summary = run.Finish();
  const LiveCamera::Frame& end = run.live_end();
  if (end.status == LiveCamera::Status::kBadSize)
    throw InputError(end.message + " (the run's outputs are written)");
  if (camera.dataset().frames.empty() && summary.interrupt_signal == 0) throw InputError(end.message);
  return summary;
}

}  // namespace dsm
