// SPDX-License-Identifier: MIT
// The photometric bundle adjustment's problem (pba.h): the keyframes and points of one run, their
// observations' linearisation into the normal equations (pba_linearize.cc), and the steps taken on
// them (pba_problem.cc). RunPba (pba.cc) runs the Levenberg–Marquardt loop on it.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dsm/map/map.h"
#include "dsm/optimization/normal_equations.h"
#include "dsm/optimization/pba.h"
#include "dsm/photometric/residual.h"

namespace dsm::internal {

using Matrix10 = Eigen::Matrix<double, 10, 10>;
using Vector10 = Eigen::Matrix<double, 10, 1>;
using Map10x8 = Eigen::Matrix<double, 10, 8>;
constexpr int kChunks = 64;  // Fixed work split: the sums do not depend on the thread count.

// Relative parameters of a host–target pair: (xi_rel 6, a_h, b_h, a_t, b_t). Absolute ones per
// keyframe: (xi 6, a, b), xi a left increment of cam_from_world.
//   xi_rel = xi_t - Adj(T_th) xi_h     (T_th = T_tw T_hw^-1)
struct PairGeometry {
  int host = -1, target = -1;  // Problem camera indices.
  int slot = -1;               // Accumulator index; -1 when both keyframes are fixed (nothing to accumulate).
  Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t = Eigen::Vector3f::Zero();
  Map10x8 A_host = Map10x8::Zero(), A_target = Map10x8::Zero();  // d(relative) / d(absolute)
};

struct PairAccumulator {
  Matrix10 H = Matrix10::Zero();
  Vector10 b = Vector10::Zero();
};

using PatternValues = std::array<float, kPatternSize>;

struct ObsState {
  int target = -1;  // Problem camera index.
  int pair = -1;    // Its host-target pair (Problem::pairs_).
  int acc = -1;     // Its pair's accumulator within its chunk; -1 when the pair has none.
  // Two linearisations side by side, the accepted one and a trial's (Problem::current_ says which
  // is which): whether the observation takes part, and its gradient weights. The energy of a
  // trial step uses the accepted ones, so a step is judged on the function its Gauss–Newton model
  // approximates.
  std::array<bool, 2> enabled{true, true};
  std::array<PatternValues, 2> weight_g{};
  // Its weighted residuals sqrt(w_g) r at that linearisation's state; valid: it projected.
  std::array<bool, 2> valid{false, false};
  std::array<PatternValues, 2> residual{};
  std::array<bool, 2> texture_lost{false, false};  // At that state (texture_loss.h): takes no part.
  int x = -1, y = -1;  // Where it last projected at this level (for prefetching); -1: not yet.
};

struct PointState {
  int id = -1;
  int host = -1;  // Problem camera index.
  bool frozen = false;  // Hosted by a frozen keyframe (Keyframe::frozen): its depth stays.
  HostPatch patch;
  bool patch_ok = false;
  std::vector<ObsState> obs;
};

// One adjustment: its cameras (free or fixed), points and observations, with each observation
// linearised twice over (the accepted state and a trial step's).
class Problem {
 public:
  Problem(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const std::vector<int>& held,
          const PbaOptions& options);

  // Robust energy of the 8 pixels given sqrt(w_g) per pixel; counts pixels above the inlier
  // threshold into *bad. The t-distribution's is computed lane-wise (vectorised) with the values
  // ErrorModel::Energy gives, summed in pixel order.
  static double PixelEnergy(const PatternValues& residuals, const PatternValues& sqrt_weight_g, const ErrorModel& model,
                            int* bad);

  int NumCameras() const { return static_cast<int>(cams_.size()); }
  const std::vector<int>& Cameras() const { return cams_; }  // Keyframe ids.
  int NumFixed() const { return static_cast<int>(std::count(fixed_.begin(), fixed_.end(), true)); }
  int NumPoints() const { return static_cast<int>(points_.size()); }
  int NumObservations() const { return num_obs_; }

  void SetLevel(int level);

  // Fits each camera's error model to the current residuals of the observations in it. Residuals
  // are gathered in parallel chunks and concatenated in point order; the fits run in parallel per
  // camera: the result is that of the sequential loop.
  void FitModels();

  // The same fit from the residuals of the accepted linearisation, which was made at the current
  // state (a rejected step restores it): after the last level, without another pass.
  void FitModelsFromLinearization();

  // Builds the normal equations at the current state and accepts them as the linearisation the
  // next step is taken from; returns the energy of the observations taking part.
  double Linearize(NormalEquations* eq);

  // One pass over the observations at a trial state: `judged` is its energy on the accepted
  // linearisation's observation set and gradient weights (what the step is judged on), and *eq,
  // `energy` the normal equations and energy of the trial's own linearisation, which deciding
  // anew which observations take part in it (> skip ratio of bad pixels: weight 0). Accept()
  // makes the latter the current linearisation; otherwise it is discarded.
  struct Trial {
    double judged = 0.0, energy = 0.0;
  };
  void Accept() { current_ ^= 1; }
  Trial LinearizeTrial(NormalEquations* eq);

  struct Backup {
    std::vector<SE3d> poses;
    std::vector<AffineBrightness> affine;
    std::vector<float> idepth;
  };
  Backup Save() const;
  void Restore(const Backup& b);

  // Applies the step; returns true when it is below the convergence thresholds.
  bool Apply(const Solution& step);

  // After the PBA: marks observations with too many bad pixels (level 0, fitted models), by the
  // residuals of the accepted linearisation (and the models fitted to them), and those whose
  // texture was lost there (counted into *texture_lost); returns how many it marked.
  int MarkOutliers(int* texture_lost);

 private:
  // The target pixels of point i's observations, where they last projected (they move little
  // between iterations); sampling them is memory-bound otherwise.
  void Prefetch(size_t i) const {
    if (i >= points_.size()) return;
    for (const ObsState& o : points_[i].obs) {
      if (o.x >= 0) map_->keyframe(cams_[o.target]).Pyramid().Prefetch(level_, o.x, o.y, 2);
    }
  }
  static void Remember(const ObservationResiduals& res, ObsState* o) {
    o->x = static_cast<int>(res.center_target.x());
    o->y = static_cast<int>(res.center_target.y());
  }

  // The host-target pairs the observations use, in (host, target) order, those with a free keyframe
  // numbered as accumulator slots; and per chunk of points (fixed split) the slots its
  // observations add to, numbered locally: a chunk's accumulators are only the ones it uses (a
  // dense chunk x slot table would be tens of MB, zeroed on every linearisation).
  void IndexPairs();

  void UpdatePairs();

  bool Evaluate(const PointState& ps, const ObsState& o, Derivatives derivatives, ObservationResiduals* res) const;

  // Whether the observation's target lost the point's texture (texture_loss.h), judged at the
  // finest level only: at the coarser ones the adjustment is still pulling re-observations into
  // place (at a lap's end a pattern may rest beside its texture until they converge).
  bool TextureLostAtLevel(const PointState& ps, const ObservationResiduals& res) const {
    return level_ == 0 && options_.texture_loss.max_variance_ratio > 0.0 &&
           TextureLost(ps.patch, res, map_->point(ps.id).idepth, options_.texture_loss);
  }
  // Whether the point's residuals take part in the model fits: with pba.refit_all_models false,
  // only points hosted by free keyframes.
  bool FitsModels(const PointState& ps) const { return options_.refit_all_models || !fixed_[ps.host]; }

  // Fits the error models (pba_models.h) and stores the fitted ones in their keyframes.
  void FitFromChunks(const std::vector<std::vector<std::vector<float>>>& chunk_residuals);

  static PatternValues SqrtOf(const PatternValues& v);
  static double InvalidEnergy(const ErrorModel& model) {
    return kPatternSize * model.Energy(2.0 * model.inlier_threshold);
  }

  // Linearises point i's observations into the trial slot (returns their energy) and adds their
  // energy on the accepted slot's set and weights to *judged.
  double LinearizePoint(size_t i, std::vector<PairAccumulator>* pairs, NormalEquations::PointBlock* block,
                        double* judged);

  Map* map_;
  PinholeCamera camera_;
  PbaOptions options_;
  std::vector<int> cams_;
  std::vector<bool> fixed_;
  std::vector<PointState> points_;
  std::vector<ErrorModel> models_;
  std::vector<PairGeometry> pairs_;
  std::vector<std::vector<PairAccumulator>> chunk_pairs_;
  std::vector<int> chunk_slots_;                               // Accumulators per chunk.
  std::vector<std::vector<std::pair<int, int>>> slot_chunks_;  // Per slot: (chunk, local index), chunk order.
  int num_obs_ = 0;
  int current_ = 0;  // Slot of the accepted linearisation in ObsState.
  int level_ = 0;
  PinholeCamera level_camera_;
};

}  // namespace dsm::internal
