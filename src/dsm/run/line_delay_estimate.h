// SPDX-License-Identifier: MIT
// The line delay of a camera whose calibration says nothing about its shutter, estimated from the
// recording itself in a first pass over its opening frames.
//
// The system runs sequentially over the opening frames once per candidate delay, each run with the
// rolling-shutter model of its delay (tracking/rolling_shutter.h); a candidate's score is the
// median, over the frames it tracked, of the tracking alignment's RMSE. The delay that explains
// the images best leaves the smallest residuals: the rows of a turning camera land where that
// delay puts them, and the map's points where the frames agree.
//   Candidates: readouts of 0, 1/n, ..., n/n of the frame interval (delay = readout / rows; n = 8
//   for 640x480, more for a smaller image, as many runs for the same cost, from 4 to 16: the dip
//   at the right delay is a few milliseconds of readout wide); then half and a quarter of a step
//   either side of the best; the estimate is the vertex of the parabola fitted (least squares) to
//   the scores within two steps of the best, which evens out the runs' own scatter (the best
//   itself where the fit has no minimum). Loop closure is off in these runs, which take the
//   opening kLineDelayFrames frames of a 640x480 camera, up to three times as many of a smaller one.
//   A delay other than 0 is kept only where its score is below kLineDelayGain times the global
//   shutter's (else the search ends after the coarse runs): a run differs from the next in which
//   frames become keyframes, which alone moves the score by up to a tenth. Measured, the best
//   score over the global shutter's: global shutters 0.93 (the room), 0.95 (EuRoC), 0.98 (loop),
//   1 (orbit, pan, forward, handheld); rolling shutters 0.75-0.77 (handheld 640x480, 30 us per
//   row), 0.88 (handheld 320x240, 60 us per row).
// A run whose frames never start a map, or that tracks fewer than half of them, scores infinity.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/io/dataset.h"
#include "dsm/run/run.h"

namespace dsm {

struct LineDelayEstimate {
  double line_delay_us = 0.0;
  std::vector<std::pair<double, double>> trials;  // (delay us, score), in the order tried.
  int first_frame = 0, frames = 0;                // The opening frames run.
  double seconds = 0.0;                           // The whole estimate's wall time.
  std::string note;                               // Why no delay was kept, when none was.
};

constexpr int kLineDelayFrames = 90;  // The opening frames run per candidate.
constexpr double kLineDelayGain = 0.9;

// Over frames options.start .. +kLineDelayFrames of `dataset` (fewer when it ends first; fewer than
// 30: no estimate, 0), with `options.system`.
LineDelayEstimate EstimateLineDelay(const Dataset& dataset, const RunOptions& options);

// {"line_delay_us", "frames", "first_frame", "seconds", "trials": [[delay us, score or null]],
// "note"}.
nlohmann::json LineDelayJson(const LineDelayEstimate& estimate);

// "line delay: 31.2 us per row, estimated from frames 0..119 (11 runs, 14.2 s)", or why 0.
std::string LineDelayLine(const LineDelayEstimate& estimate);

}  // namespace dsm
