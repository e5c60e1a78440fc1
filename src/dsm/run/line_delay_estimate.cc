// SPDX-License-Identifier: MIT
#include "dsm/run/line_delay_estimate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Dense>

#include "dsm/run/frame_reader.h"
#include "dsm/system/system.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {

namespace {

// Kept as read (8-bit: a third of the memory of the frames ready for tracking), prepared per run.
struct OpeningFrames {
  std::vector<int> index;
  std::vector<Image<uint8_t>> image;
};

// The median tracking RMSE of a sequential run over the frames with a rolling shutter of
// `line_delay_us` (infinity: no map, or fewer than half of the frames tracked).
double Score(const OpeningFrames& frames, const Dataset& dataset, const Undistorter& undistorter,
             SystemOptions options, double line_delay_us) {
  options.loop_closure.enabled = false;  // The opening frames close no loop.
  SystemSetup setup;
  setup.line_delay_s = line_delay_us * 1e-6;
  System system(undistorter.output(), options, setup);
  std::vector<double> rmse;
  for (size_t k = 0; k < frames.index.size(); ++k) {
    const int i = frames.index[k];
    const FrameReport r = system.Process(i, dataset.frames[i].t_ns,
                                         PrepareFrame(dataset, undistorter, frames.image[k]),
                                         dataset.frames[i].exposure_ms);
    if (r.status == TrackingStatus::kOk && r.tracking_rmse > 0.0) rmse.push_back(r.tracking_rmse);
  }
  system.Finish();
  if (rmse.size() < frames.index.size() / 2) return std::numeric_limits<double>::infinity();
  return Median(rmse);
}

}  // namespace

LineDelayEstimate EstimateLineDelay(const Dataset& dataset, const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  LineDelayEstimate out;
  const Undistorter undistorter = FrameUndistorter(dataset, options.system);
  // A System of the run's own options first: what they name and cannot load (a vocabulary file)
  // is said before the runs, which leave loop closure out.
  System(undistorter.output(), options.system).Finish();
  // A run's cost against a 640x480 camera's: a smaller image affords more frames (up to 3x) and
  // more candidates.
  const double cheaper = 640.0 * 480.0 / (static_cast<double>(undistorter.output().width) * undistorter.output().height);
  const int budget = static_cast<int>(kLineDelayFrames * std::clamp(cheaper, 1.0, 3.0));
  const int end = std::min<int>(static_cast<int>(dataset.size()), options.start + budget);
  out.first_frame = options.start;
  OpeningFrames frames;
  for (int i = options.start; i < end; ++i) {
    try {
      frames.image.push_back(dataset.LoadImage(i));
      frames.index.push_back(i);
    } catch (const InputError&) {
      // A frame that cannot be read is the run's to report; the estimate goes without it.
    }
  }
  out.frames = static_cast<int>(frames.index.size());
  if (out.frames < 30) {
    out.note = "too few frames to tell";
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  std::vector<double> intervals;
  for (size_t k = 1; k < frames.index.size(); ++k)
    intervals.push_back(1e-3 * (dataset.frames[frames.index[k]].t_ns - dataset.frames[frames.index[k - 1]].t_ns) /
                        (frames.index[k] - frames.index[k - 1]));
  // The longest delay whose readout fits in a frame interval.
  const double max_us = Median(intervals) / dataset.camera.height;
  const auto score = [&](double delay_us) {
    for (const auto& [d, s] : out.trials)
      if (d == delay_us) return s;
    const double s = Score(frames, dataset, undistorter, options.system, delay_us);
    out.trials.emplace_back(delay_us, s);
    return s;
  };
  // As many steps as a 640x480 camera's eight cost (the dip at the right delay is a few
  // milliseconds of readout wide), from 4 to 16.
  const int steps = std::clamp(static_cast<int>(std::lround(8.0 * cheaper)), 4, 16);
  double step = max_us / steps;
  double best = 0.0;
  for (int k = 0; k <= steps; ++k)
    if (score(k * step) < score(best)) best = k * step;
  const auto finish = [&](double delay_us, const char* note) {
    out.line_delay_us = delay_us;
    out.note = note;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };
  constexpr const char* kNoDelay = "no delay explains the images clearly better than a global shutter";
  if (!(score(best) < kLineDelayGain * score(0.0))) return finish(0.0, kNoDelay);
  for (int halving = 0; halving < 2; ++halving) {
    step *= 0.5;
    const double centre = best;
    for (double d : {centre - step, centre + step})
      if (d > 0.0 && d <= max_us && score(d) < score(best)) best = d;
  }
  // The parabola fitted (least squares) to the scores within two coarse steps of the best: each
  // run's score scatters by its own keyframe choices, which a wider fit evens out.
  const double reach = 2.0 * max_us / steps;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int fitted = 0;
  for (const auto& [d, s] : out.trials) {
    if (!std::isfinite(s) || std::abs(d - best) > reach + 1e-6) continue;
    const Eigen::Vector3d x(1.0, d - best, (d - best) * (d - best));
    normal += x * x.transpose();
    rhs += x * s;
    ++fitted;
  }
  double estimate = best;
  if (fitted >= 4) {
    const Eigen::Vector3d c = normal.ldlt().solve(rhs);
    if (c[2] > 0.0) estimate = std::clamp(best - 0.5 * c[1] / c[2], best - reach, best + reach);
  }
  return finish(std::clamp(estimate, 0.0, max_us), "");
}

nlohmann::json LineDelayJson(const LineDelayEstimate& e) {
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& [delay_us, score] : e.trials)
    trials.push_back({delay_us, std::isfinite(score) ? nlohmann::json(score) : nlohmann::json()});
  return {{"line_delay_us", e.line_delay_us}, {"frames", e.frames},  {"first_frame", e.first_frame},
          {"seconds", e.seconds},             {"trials", trials},    {"note", e.note}};
}

std::string LineDelayLine(const LineDelayEstimate& e) {
  char text[256];
  std::snprintf(text, sizeof(text), "line delay: %.1f us per row, estimated from frames %d..%d (%zu runs, %.1f s)%s%s",
                e.line_delay_us, e.first_frame, e.first_frame + e.frames - 1, e.trials.size(), e.seconds,
                e.note.empty() ? "" : ": ", e.note.c_str());
  return text;
}

}  // namespace dsm
