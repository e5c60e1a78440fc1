// SPDX-License-Identifier: MIT
// Trajectory error metrics, with the definitions of the field's reference evaluation tool:
//
//   alignment  Umeyama on the associated positions, est -> ref (none, SE(3) or Sim(3));
//   APE        e_i = | t(ref_i) - t(S est_i) |;
//   RPE        E_ij = (ref_i^-1 ref_j)^-1 (est_i^-1 est_j), e = |t(E_ij)|, over consecutive pairs
//              (i, j) of an index list: every `delta` frames, or each time the estimate's path
//              has grown by >= `delta` metres since the last index;
//   statistics rmse, mean, median, std (population), min, max.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dsm/eval/association.h"
#include "dsm/lie/sim3.h"

namespace dsm {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
  size_t count = 0;
};

// Throws InputError on an empty set.
ErrorStats ComputeStats(std::vector<double> errors);

enum class Alignment { kNone, kSE3, kSim3 };
Alignment ParseAlignment(const std::string& name, const std::string& where);

enum class RpeUnit { kFrames, kMeters };

struct EvalOptions {
  Alignment align = Alignment::kNone;
  double max_dt_s = 0.01;     // Association tolerance (stamped trajectories).
  std::optional<double> rpe_delta;  // Computes RPE when set (> 0).
  RpeUnit rpe_unit = RpeUnit::kFrames;
  // Set: this ref_from_est is applied instead of fitting one (`align` is then not used), e.g. the
  // alignment of an earlier session's trajectory, to score a later session in the same frame and
  // scale (a map loaded and extended: dsm run --load-map).
  std::optional<Sim3d> fixed_alignment;

  void Validate() const;  // Throws InputError naming the option.
};

struct EvalResult {
  ErrorStats ape;
  size_t pairs = 0;
  Sim3d ref_from_est;  // The alignment applied to the estimate.
  std::optional<ErrorStats> rpe;
};

// `ref` and `est` are world_from_cam trajectories. Stamped pairs associate by time, unstamped by
// index. Throws InputError when nothing associates or the alignment is degenerate.
EvalResult Evaluate(const Trajectory& ref, const Trajectory& est, const EvalOptions& options);

// The reference poses paired with the estimate's (as Evaluate pairs them), moved into the
// estimate's frame by the inverse alignment (est_from_ref = result.ref_from_est^-1: rotation
// R^T R_i, position S^-1 t_i) and stamped with the estimate's times: the ground truth drawn beside
// a map. The position error in reference units is then s |t(est_k) - t(row_k)|, s = S's scale.
Trajectory ReferenceInEstimateFrame(const Trajectory& ref, const Trajectory& est, const EvalResult& result,
                                    const EvalOptions& options);

// {"ape": {rmse, mean, median, std, min, max}, "pairs": N, "scale": s, "rpe": {..., "pairs"},
//  "alignment": {"rotation_xyzw": [4], "translation": [3], "scale": s}}   (ref_from_est)
nlohmann::json ToJson(const EvalResult& result);
// The ref_from_est of a ToJson result read back: from `j`'s "alignment", or from that of its
// "keyframes" (a run's eval.json). InputError naming `where` when there is none or it is not one.
Sim3d AlignmentFromJson(const nlohmann::json& j, const std::string& where);
nlohmann::json ToJson(const ErrorStats& stats);

}  // namespace dsm
