// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba.h"

#include <algorithm>
#include <chrono>

#include "dsm/optimization/normal_equations.h"
#include "dsm/optimization/pba_problem.h"
#include "dsm/util/check.h"

namespace dsm {

void PbaOptions::Validate() const {
  if (levels < 1 || levels > 5) throw InputError("pba.levels must be within 1..5");
  if (max_iterations < 1) throw InputError("pba.max_iterations must be positive");
  if (!(initial_lambda > 0)) throw InputError("pba.initial_lambda must be positive");
  if (max_outside_observations < 0) throw InputError("pba.max_outside_observations must be non-negative");
  if (max_outside_keyframes < 0) throw InputError("pba.max_outside_keyframes must be non-negative");
  if (min_camera_observations < 0) throw InputError("pba.min_camera_observations must be non-negative");
  if (!(min_link_ratio >= 0 && min_link_ratio <= 1)) throw InputError("pba.min_link_ratio must be within 0..1");
  if (!(max_sigma_ratio == 0 || max_sigma_ratio >= 1)) throw InputError("pba.max_sigma_ratio must be 0 or at least 1");
  if (!(drop_outlier_ratio > 0 && drop_outlier_ratio <= skip_outlier_ratio && skip_outlier_ratio <= 1))
    throw InputError("pba outlier ratios must satisfy 0 < drop <= skip <= 1");
  robust.Validate();
  texture_loss.Validate();
}

PbaSummary RunPba(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const PbaOptions& options,
                  const std::vector<int>& held, const PbaYield& yield) {
  const auto t0 = std::chrono::steady_clock::now();
  options.Validate();
  PbaSummary summary;
  internal::Problem problem(map, camera, active, held, options);
  summary.keyframes = problem.NumCameras();
  summary.cameras = problem.Cameras();
  summary.fixed_keyframes = problem.NumFixed();
  summary.points = problem.NumPoints();
  summary.observations = problem.NumObservations();
  if (problem.NumPoints() == 0) return summary;
  NormalEquations eq, trial_eq;
  DSM_CHECK(yield.level < options.levels && yield.iterations >= 0, "an adjustment taken up where it never was");
  for (int level = yield.level >= 0 ? yield.level : options.levels - 1; level >= 0 && !summary.yielded; --level) {
    problem.SetLevel(level);
    problem.FitModels();
    double lambda = options.initial_lambda;
    double energy = problem.Linearize(&eq);
    if (level == 0) summary.initial_energy = energy;
    for (int it = level == yield.level ? yield.iterations : 0; it < options.max_iterations; ++it) {
      ++summary.iterations;
      const internal::Problem::Backup backup = problem.Save();
      const Solution step = SolveSchur(eq, lambda);
      const bool converged = problem.Apply(step);
      const internal::Problem::Trial trial = problem.LinearizeTrial(&trial_eq);
      if (trial.judged < energy) {
        lambda = std::max(lambda * 0.25, 1e-8);
        problem.Accept();
        std::swap(eq, trial_eq);
        energy = trial.energy;
        if (converged) break;
      } else {
        problem.Restore(backup);
        lambda *= 8.0;
        if (lambda > 1e4 || converged) break;
      }
      if (yield.now && (level > 0 || it + 1 < options.max_iterations) && yield.now()) {
        // Taken up at this level's next iteration, or at the next level after its last.
        const bool level_done = it + 1 == options.max_iterations;
        summary.yielded = true;
        summary.level = level_done ? level - 1 : level;
        summary.level_iterations = level_done ? 0 : it + 1;
        break;
      }
    }
    summary.final_energy = energy;
  }
  if (!summary.yielded) {
    problem.FitModelsFromLinearization();  // At level 0, where the loop ended.
    summary.observations_removed = problem.MarkOutliers(&summary.observations_texture_lost);
  }
  summary.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace dsm
