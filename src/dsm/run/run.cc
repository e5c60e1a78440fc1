// SPDX-License-Identifier: MIT
#include "dsm/run/run.h"

#include <cstdio>

#include "dsm/run/dataset_run.h"
#include "dsm/run/line_delay_estimate.h"
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
  // (Frames the run cannot start from are its constructor's message.)
  const bool startable = options.start >= 0 && options.start + 1 < static_cast<int>(dataset.size());
  if (dataset.line_delay_source != LineDelaySource::kUnknown || !startable) {
    DatasetRun run(dataset, options, out_dir);
    run.FeedFrames();
    return run.Finish();
  }
  // The calibration says nothing of the shutter: a first pass over the opening frames tells.
  const LineDelayEstimate estimate = EstimateLineDelay(dataset, options);
  if (!options.quiet) std::printf("%s\n", LineDelayLine(estimate).c_str());
  Dataset estimated = dataset;
  estimated.line_delay_us = estimate.line_delay_us;
  estimated.line_delay_source = LineDelaySource::kEstimated;
  DatasetRun run(estimated, options, out_dir);
  run.AddStats("line_delay_estimate", LineDelayJson(estimate));
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
