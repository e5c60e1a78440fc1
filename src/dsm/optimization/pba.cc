// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/optimization/normal_equations.h"
#include "dsm/optimization/pba_models.h"
#include "dsm/optimization/pba_selection.h"
#include "dsm/util/check.h"
#include "dsm/util/simd.h"

namespace dsm {

void PbaOptions::Validate() const {
  if (levels < 1 || levels > 5) throw InputError("pba.levels must be within 1..5");
  if (max_iterations < 1) throw InputError("pba.max_iterations must be positive");
  if (!(initial_lambda > 0)) throw InputError("pba.initial_lambda must be positive");
  if (max_outside_observations < 0) throw InputError("pba.max_outside_observations must be non-negative");
  if (max_outside_keyframes < 0) throw InputError("pba.max_outside_keyframes must be non-negative");
  if (outside_observations_per_point < 0) throw InputError("pba.outside_observations_per_point must be non-negative");
  if (min_camera_observations < 0) throw InputError("pba.min_camera_observations must be non-negative");
  if (!(min_link_ratio >= 0 && min_link_ratio <= 1)) throw InputError("pba.min_link_ratio must be within 0..1");
  if (!(max_sigma_ratio == 0 || max_sigma_ratio >= 1)) throw InputError("pba.max_sigma_ratio must be 0 or at least 1");
  if (!(drop_outlier_ratio > 0 && drop_outlier_ratio <= skip_outlier_ratio && skip_outlier_ratio <= 1))
    throw InputError("pba outlier ratios must satisfy 0 < drop <= skip <= 1");
  robust.Validate();
}

namespace {

using Matrix10 = Eigen::Matrix<double, 10, 10>;
using Vector10 = Eigen::Matrix<double, 10, 1>;
using Map10x8 = Eigen::Matrix<double, 10, 8>;
constexpr int kChunks = 64;  // Fixed work split: the sums do not depend on the thread count.

// Relative parameters of a host–target pair: (xi_rel 6, a_h, b_h, a_t, b_t). Absolute ones per
// keyframe: (xi 6, a, b), xi a left increment of cam_from_world.
//   xi_rel = xi_t - Adj(T_th) xi_h     (T_th = T_tw T_hw^-1)
struct PairGeometry {
  int host = -1, target = -1;  // Problem camera indices.
  int slot = -1;  // Accumulator index; -1 when both keyframes are fixed (nothing to accumulate).
  Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t = Eigen::Vector3f::Zero();
  Map10x8 A_host = Map10x8::Zero(), A_target = Map10x8::Zero();  // d(relative) / d(absolute)
};

struct PairAccumulator {
  Matrix10 H = Matrix10::Zero();
  Vector10 b = Vector10::Zero();
};

using PatternValues = std::array<float, kPatternSize>;

// One observation's terms of its pair's normal equations, with J = [J_pose J_affine] (8 x 10,
// column-major), W = diag(w) and A = J^T W:  H += A J,  b += A r,  h = A J_rho.
// Each sum runs over the 8 pixels in order, as Eigen's coefficient-wise products of these sizes
// do, so the floats are the same; as plain loops the AVX2 clone takes four rows a vector.
DSM_SIMD_CLONES void AccumulateObservation(const double* J, const double* w, const double* r, const double* J_rho,
                                           double* H, double* b, double* h) {
  constexpr int n = kPatternSize, m = 10;
  alignas(32) double A[n][m];  // A[k][i] = J(k, i) w_k: column k of A.
  for (int k = 0; k < n; ++k)
#pragma omp simd
    for (int i = 0; i < m; ++i) A[k][i] = J[i * n + k] * w[k];
  for (int j = 0; j < m; ++j) {
    const double* Jj = J + j * n;
#pragma omp simd
    for (int i = 0; i < m; ++i) {
      double sum = A[0][i] * Jj[0];
      for (int k = 1; k < n; ++k) sum = sum + A[k][i] * Jj[k];
      H[j * m + i] += sum;
    }
  }
#pragma omp simd
  for (int i = 0; i < m; ++i) {
    double sum_b = A[0][i] * r[0], sum_h = A[0][i] * J_rho[0];
    for (int k = 1; k < n; ++k) {
      sum_b = sum_b + A[k][i] * r[k];
      sum_h = sum_h + A[k][i] * J_rho[k];
    }
    b[i] += sum_b;
    h[i] = sum_h;
  }
}

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
  int x = -1, y = -1;  // Where it last projected at this level (for prefetching); -1: not yet.
};

struct PointState {
  int id = -1;
  int host = -1;        // Problem camera index.
  HostPatch patch;
  bool patch_ok = false;
  std::vector<ObsState> obs;
};

class Problem {
 public:
  Problem(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const std::vector<int>& held,
          const PbaOptions& options)
      : map_(map), camera_(camera), options_(options) {
    PbaSelection selection = SelectPbaProblem(*map, active, held, options);
    for (size_t c = 0; c < selection.cams.size(); ++c) {
      Keyframe& k = map->keyframe(selection.cams[c]);
      if (!selection.fixed[c]) k.most_pba_links = std::max(k.most_pba_links, selection.links[c]);
    }
    cams_ = std::move(selection.cams);
    fixed_ = std::move(selection.fixed);
    num_obs_ = selection.num_observations;
    points_.reserve(selection.points.size());
    for (const PbaSelection::PointObservations& po : selection.points) {
      PointState ps;
      ps.id = po.id;
      ps.host = po.host;
      for (int t : po.targets) ps.obs.push_back({t});
      points_.push_back(std::move(ps));
    }
    map->LoadPyramids(cams_);
    models_.resize(cams_.size());
    for (size_t c = 0; c < cams_.size(); ++c) models_[c] = map->keyframe(cams_[c]).error_model;
    IndexPairs();
  }

  int NumCameras() const { return static_cast<int>(cams_.size()); }
  int NumFixed() const { return static_cast<int>(std::count(fixed_.begin(), fixed_.end(), true)); }
  int NumPoints() const { return static_cast<int>(points_.size()); }
  int NumObservations() const { return num_obs_; }

  void SetLevel(int level) {
    level_ = level;
    level_camera_ = camera_.AtLevel(level);
    const float scale = 1.f / static_cast<float>(1 << level);
    tbb::parallel_for(size_t{0}, points_.size(), [&](size_t i) {
      PointState& ps = points_[i];
      const Point& p = map_->point(ps.id);
      const Eigen::Vector2f px((p.pixel.x() + 0.5f) * scale - 0.5f, (p.pixel.y() + 0.5f) * scale - 0.5f);
      ps.patch_ok = SampleHostPatch(map_->keyframe(cams_[ps.host]).Pyramid(), level, px, &ps.patch);
      for (ObsState& o : ps.obs) o.x = o.y = -1;
    });
  }

  // Fits each camera's error model to the current residuals of the observations in it. Residuals
  // are gathered in parallel chunks and concatenated in point order; the fits run in parallel per
  // camera: the result is that of the sequential loop.
  void FitModels() {
    UpdatePairs();
    const size_t n = cams_.size();
    std::vector<std::vector<std::vector<float>>> chunk_residuals(kChunks, std::vector<std::vector<float>>(n));
    tbb::parallel_for(0, kChunks, [&](int chunk) {
      const size_t begin = points_.size() * chunk / kChunks, end = points_.size() * (chunk + 1) / kChunks;
      for (size_t i = begin; i < end; ++i) {
        PointState& ps = points_[i];
        if (i + 1 < end) Prefetch(i + 1);
        if (!ps.patch_ok) continue;
        const bool skip_fit = !FitsModels(ps);
        for (ObsState& o : ps.obs) {
          ObservationResiduals res;
          if (!Evaluate(ps, o, false, &res)) continue;
          Remember(res, &o);
          if (skip_fit) continue;
          std::vector<float>& out = chunk_residuals[chunk][o.target];
          for (int k = 0; k < kPatternSize; ++k) out.push_back(std::sqrt(res.weight_g[k]) * res.r[k]);
        }
      }
    });
    FitFromChunks(chunk_residuals);
  }

  // The same fit from the residuals of the accepted linearisation, which was made at the current
  // state (a rejected step restores it): after the last level, without another pass.
  void FitModelsFromLinearization() {
    const size_t n = cams_.size();
    std::vector<std::vector<std::vector<float>>> chunk_residuals(1, std::vector<std::vector<float>>(n));
    for (const PointState& ps : points_) {
      if (!ps.patch_ok || !FitsModels(ps)) continue;
      for (const ObsState& o : ps.obs) {
        if (!o.valid[current_]) continue;
        std::vector<float>& out = chunk_residuals[0][o.target];
        out.insert(out.end(), o.residual[current_].begin(), o.residual[current_].end());
      }
    }
    FitFromChunks(chunk_residuals);
  }

  // Builds the normal equations at the current state and accepts them as the linearisation the
  // next step is taken from; returns the energy of the observations taking part.
  double Linearize(NormalEquations* eq) {
    const Trial trial = LinearizeTrial(eq);
    Accept();
    return trial.energy;
  }

  // One pass over the observations at a trial state: `judged` is its energy on the accepted
  // linearisation's observation set and gradient weights (what the step is judged on), and *eq,
  // `energy` the normal equations and energy of the trial's own linearisation, which deciding
  // anew which observations take part in it (> skip ratio of bad pixels: weight 0). Accept()
  // makes the latter the current linearisation; otherwise it is discarded.
  struct Trial {
    double judged = 0.0, energy = 0.0;
  };
  void Accept() { current_ ^= 1; }
  Trial LinearizeTrial(NormalEquations* eq) {
    UpdatePairs();
    eq->Reset(fixed_, NumPoints());
    // Per chunk, one accumulator per pair with a free keyframe that its observations use.
    chunk_pairs_.resize(kChunks);
    for (int chunk = 0; chunk < kChunks; ++chunk) chunk_pairs_[chunk].assign(chunk_slots_[chunk], PairAccumulator{});
    auto& chunk_pairs = chunk_pairs_;
    std::vector<double> chunk_energy(kChunks, 0.0), chunk_judged(kChunks, 0.0);
    tbb::parallel_for(0, kChunks, [&](int chunk) {
      const size_t begin = points_.size() * chunk / kChunks, end = points_.size() * (chunk + 1) / kChunks;
      for (size_t i = begin; i < end; ++i) {
        if (i + 1 < end) Prefetch(i + 1);
        chunk_energy[chunk] += LinearizePoint(i, &chunk_pairs[chunk], &eq->points[i], &chunk_judged[chunk]);
      }
    });
    Trial trial;
    for (int chunk = 0; chunk < kChunks; ++chunk) {
      trial.energy += chunk_energy[chunk];
      trial.judged += chunk_judged[chunk];
    }
    // Pairs in (host, target) order, each summed over the chunks in order: the sums do not depend
    // on the thread count.
    for (const PairGeometry& g : pairs_) {
      if (g.slot < 0) continue;
      PairAccumulator sum;
      for (const auto& [chunk, local] : slot_chunks_[g.slot]) {
        sum.H += chunk_pairs[chunk][local].H;
        sum.b += chunk_pairs[chunk][local].b;
      }
      // Only the free cameras' blocks (a fixed camera's rows drop out of the solve).
      const int ih = eq->block[g.host], it = eq->block[g.target];
      if (ih >= 0) {
        eq->H_cc.block<8, 8>(ih, ih) += g.A_host.transpose() * sum.H * g.A_host;
        eq->b_c.segment<8>(ih) += g.A_host.transpose() * sum.b;
      }
      if (it >= 0) {
        eq->H_cc.block<8, 8>(it, it) += g.A_target.transpose() * sum.H * g.A_target;
        eq->b_c.segment<8>(it) += g.A_target.transpose() * sum.b;
      }
      if (ih >= 0 && it >= 0) {
        const Eigen::Matrix<double, 8, 8> ht = g.A_host.transpose() * sum.H * g.A_target;
        eq->H_cc.block<8, 8>(ih, it) += ht;
        eq->H_cc.block<8, 8>(it, ih) += ht.transpose();
      }
    }
    return trial;
  }

  struct Backup {
    std::vector<SE3d> poses;
    std::vector<AffineBrightness> affine;
    std::vector<float> idepth;
  };
  Backup Save() const {
    Backup b;
    for (int id : cams_) {
      b.poses.push_back(map_->keyframe(id).cam_from_world);
      b.affine.push_back(map_->keyframe(id).affine);
    }
    for (const auto& ps : points_) b.idepth.push_back(map_->point(ps.id).idepth);
    return b;
  }
  void Restore(const Backup& b) {
    for (size_t c = 0; c < cams_.size(); ++c) {
      map_->keyframe(cams_[c]).cam_from_world = b.poses[c];
      map_->keyframe(cams_[c]).affine = b.affine[c];
    }
    for (size_t i = 0; i < points_.size(); ++i) map_->point(points_[i].id).idepth = b.idepth[i];
  }

  // Applies the step; returns true when it is below the convergence thresholds.
  bool Apply(const Solution& step) {
    double max_rot = 0, max_trans = 0, max_a = 0, max_b = 0;
    for (size_t c = 0; c < cams_.size(); ++c) {
      if (fixed_[c]) continue;
      const CameraVector d = step.cameras.segment<kCameraParams>(kCameraParams * c);
      Keyframe& kf = map_->keyframe(cams_[c]);
      kf.cam_from_world = SE3d::Exp(d.head<6>()) * kf.cam_from_world;
      kf.affine.a += d(6);
      kf.affine.b += d(7);
      max_trans = std::max(max_trans, d.head<3>().norm());
      max_rot = std::max(max_rot, d.segment<3>(3).norm());
      max_a = std::max(max_a, std::abs(d(6)));
      max_b = std::max(max_b, std::abs(d(7)));
    }
    double mean_idepth = 0.0;
    for (size_t i = 0; i < points_.size(); ++i) {
      float& rho = map_->point(points_[i].id).idepth;
      rho = std::max(1e-4f, rho + static_cast<float>(step.points(i)));
      mean_idepth += rho;
    }
    mean_idepth /= std::max<size_t>(1, points_.size());
    return max_rot < options_.max_rotation_step && max_trans * mean_idepth < options_.max_translation_step &&
           max_a < options_.max_a_step && max_b < options_.max_b_step;
  }

  // After the PBA: marks observations with too many bad pixels (level 0, fitted models), by the
  // residuals of the accepted linearisation (and the models fitted to them).
  int MarkOutliers() {
    int removed = 0;
    for (PointState& ps : points_) {
      Point& p = map_->point(ps.id);
      for (size_t j = 0; j < ps.obs.size(); ++j) {
        const ObsState& o = ps.obs[j];
        int bad = kPatternSize;
        if (ps.patch_ok && o.valid[current_]) {
          bad = 0;
          for (float r : o.residual[current_]) bad += models_[o.target].IsOutlier(r);
        }
        Observation* obs = p.FindObservation(cams_[o.target]);
        if (bad > options_.drop_outlier_ratio * kPatternSize) {
          obs->outlier = true;
          ++removed;
        }
      }
    }
    return removed;
  }

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
  // dense chunk x slot table was tens of MB, zeroed on every linearisation).
  void IndexPairs() {
    const int n = NumCameras();
    std::vector<int> index(static_cast<size_t>(n) * n, -1);
    for (const PointState& ps : points_)
      for (const ObsState& o : ps.obs) index[ps.host * n + o.target] = 0;
    int num_slots = 0;
    for (int h = 0; h < n; ++h)
      for (int t = 0; t < n; ++t) {
        if (index[h * n + t] < 0) continue;
        index[h * n + t] = static_cast<int>(pairs_.size());
        PairGeometry g;
        g.host = h;
        g.target = t;
        if (!(fixed_[h] && fixed_[t])) g.slot = num_slots++;
        pairs_.push_back(g);
      }
    slot_chunks_.assign(num_slots, {});
    chunk_slots_.assign(kChunks, 0);
    std::vector<int> local(num_slots, -1);
    for (int chunk = 0; chunk < kChunks; ++chunk) {
      const size_t begin = points_.size() * chunk / kChunks, end = points_.size() * (chunk + 1) / kChunks;
      std::vector<int> used;
      for (size_t i = begin; i < end; ++i)
        for (ObsState& o : points_[i].obs) {
          o.pair = index[points_[i].host * n + o.target];
          const int slot = pairs_[o.pair].slot;
          if (slot < 0) continue;
          if (local[slot] < 0) {
            local[slot] = chunk_slots_[chunk]++;
            used.push_back(slot);
            slot_chunks_[slot].emplace_back(chunk, local[slot]);
          }
          o.acc = local[slot];
        }
      for (int slot : used) local[slot] = -1;
    }
  }

  void UpdatePairs() {
    for (PairGeometry& g : pairs_) {
      const SE3d T_th =
          map_->keyframe(cams_[g.target]).cam_from_world * map_->keyframe(cams_[g.host]).cam_from_world.Inverse();
      g.R = T_th.Rotation().cast<float>();
      g.t = T_th.Translation().cast<float>();
      g.A_host.setZero();
      g.A_host.topLeftCorner<6, 6>() = -T_th.Adj();
      g.A_host(6, 6) = g.A_host(7, 7) = 1.0;
      g.A_target.setZero();
      g.A_target.topLeftCorner<6, 6>().setIdentity();
      g.A_target(8, 6) = g.A_target(9, 7) = 1.0;
    }
  }

  bool Evaluate(const PointState& ps, const ObsState& o, bool jacobians, ObservationResiduals* res) const {
    return Evaluate(ps, o, jacobians ? Derivatives::kAll : Derivatives::kNone, res);
  }
  bool Evaluate(const PointState& ps, const ObsState& o, Derivatives derivatives, ObservationResiduals* res) const {
    const PairGeometry& g = pairs_[o.pair];
    const Keyframe& host = map_->keyframe(cams_[ps.host]);
    const Keyframe& target = map_->keyframe(cams_[o.target]);
    ObservationInput in;
    in.camera = &level_camera_;
    in.target = &target.Pyramid();
    in.level = level_;
    in.R = g.R;
    in.t = g.t;
    in.idepth = map_->point(ps.id).idepth;
    in.host_affine = host.affine;
    in.target_affine = target.affine;
    in.host_exposure = host.exposure;
    in.target_exposure = target.exposure;
    return EvaluateObservation(ps.patch, in, derivatives, res);
  }

  // Whether the point's residuals take part in the model fits: with pba.refit_all_models false,
  // only points hosted by free keyframes.
  bool FitsModels(const PointState& ps) const { return options_.refit_all_models || !fixed_[ps.host]; }

  // Fits the error models (pba_models.h) and stores the fitted ones in their keyframes.
  void FitFromChunks(const std::vector<std::vector<std::vector<float>>>& chunk_residuals) {
    for (int c : FitPbaModels(chunk_residuals, cams_, fixed_, options_, &models_))
      map_->keyframe(cams_[c]).error_model = models_[c];
  }

  // Robust energy of the 8 pixels given sqrt(w_g) per pixel; counts pixels above the inlier
  // threshold into *bad. The t-distribution's is computed lane-wise (vectorised) with the values
  // ErrorModel::Energy gives, summed in pixel order.
  static double PixelEnergy(const PatternValues& residuals, const PatternValues& sqrt_weight_g,
                            const ErrorModel& model, int* bad) {
    double e = 0.0;
    int n_bad = 0;
    if (model.kind == RobustKind::kStudentT) {
      alignas(32) float log_terms[kPatternSize];
      alignas(32) int outlier[kPatternSize];
      const float inv = static_cast<float>(1.0 / (model.nu * model.sigma * model.sigma));
      const double threshold = model.inlier_threshold;
#pragma omp simd
      for (int k = 0; k < kPatternSize; ++k) {
        const float r = sqrt_weight_g[k] * residuals[k];
        log_terms[k] = FastLog1p(r * r * inv);
        outlier[k] = static_cast<double>(std::abs(r)) > threshold;
      }
      const double scale = 0.5 * (model.nu + 1.0);
      for (int k = 0; k < kPatternSize; ++k) {
        e += scale * log_terms[k];
        n_bad += outlier[k];
      }
    } else {
      for (int k = 0; k < kPatternSize; ++k) {
        const double r = sqrt_weight_g[k] * residuals[k];
        e += model.Energy(r);
        n_bad += model.IsOutlier(r);
      }
    }
    if (bad) *bad = n_bad;
    return e;
  }
  static PatternValues SqrtOf(const PatternValues& v) {
    PatternValues out;
#pragma omp simd
    for (int k = 0; k < kPatternSize; ++k) out[k] = std::sqrt(v[k]);
    return out;
  }
  static double InvalidEnergy(const ErrorModel& model) { return kPatternSize * model.Energy(2.0 * model.inlier_threshold); }

  // Linearises point i's observations into the trial slot (returns their energy) and adds their
  // energy on the accepted slot's set and weights to *judged.
  double LinearizePoint(size_t i, std::vector<PairAccumulator>* pairs, NormalEquations::PointBlock* block,
                        double* judged) {
    PointState& ps = points_[i];
    if (!ps.patch_ok) return 0.0;
    const int cur = current_, trial = current_ ^ 1;
    double energy = 0.0;
    for (ObsState& o : ps.obs) {
      ObservationResiduals res;
      const ErrorModel& model = models_[o.target];
      // Between two fixed keyframes only the inverse depth moves.
      const PairGeometry& g = pairs_[o.pair];
      if (!Evaluate(ps, o, g.slot >= 0 ? Derivatives::kAll : Derivatives::kIdepth, &res)) {
        if (o.enabled[cur]) *judged += InvalidEnergy(model);
        o.valid[trial] = false;
        o.enabled[trial] = true;
        o.weight_g[trial] = o.weight_g[cur];  // Kept from the last linearisation that had them.
        energy += InvalidEnergy(model);
        continue;
      }
      if (o.enabled[cur]) *judged += PixelEnergy(res.r, SqrtOf(o.weight_g[cur]), model, nullptr);
      o.weight_g[trial] = res.weight_g;
      o.valid[trial] = true;
      const PatternValues sqrt_w = SqrtOf(res.weight_g);
      PatternValues& weighted = o.residual[trial];
#pragma omp simd
      for (int k = 0; k < kPatternSize; ++k) weighted[k] = sqrt_w[k] * res.r[k];
      Remember(res, &o);
      int bad = 0;
      const double e = PixelEnergy(res.r, sqrt_w, model, &bad);
      o.enabled[trial] = bad <= options_.skip_outlier_ratio * kPatternSize;
      if (!o.enabled[trial]) continue;
      energy += e;
      // Per pixel: w = w_g * w_rho(sqrt(w_g) r) (lane-wise; the product sqrt(w_g) r is exact in double).
      const Eigen::Matrix<double, kPatternSize, 1> Jr = res.J_idepth.cast<double>();
      Eigen::Matrix<double, kPatternSize, 1> w, r;
      if (model.kind == RobustKind::kStudentT) {
        const double nu1 = model.nu + 1.0, nu_s2 = model.nu * model.sigma * model.sigma;
#pragma omp simd
        for (int k = 0; k < kPatternSize; ++k) {
          const double rk = res.r[k], rw = sqrt_w[k] * rk;
          w(k) = res.weight_g[k] * (nu1 / (nu_s2 + rw * rw));
          r(k) = rk;
        }
      } else {
        for (int k = 0; k < kPatternSize; ++k) {
          const double rk = res.r[k];
          w(k) = res.weight_g[k] * model.Weight(sqrt_w[k] * rk);
          r(k) = rk;
        }
      }
      block->H_pp += Jr.dot(w.asDiagonal() * Jr);
      block->b_p += Jr.dot(w.asDiagonal() * r);
      if (g.slot < 0) continue;
      // Camera blocks and the point's coupling to the free keyframes (a fixed one's would be
      // dropped by the Schur complement and multiply a zero step in the back-substitution).
      Eigen::Matrix<double, kPatternSize, 10> Jx;
      Jx << res.J_pose.cast<double>(), res.J_affine.cast<double>();
      PairAccumulator& acc = (*pairs)[o.acc];
      Vector10 h_xp;
      AccumulateObservation(Jx.data(), w.data(), r.data(), Jr.data(), acc.H.data(), acc.b.data(), h_xp.data());
      if (!fixed_[ps.host]) NormalEquations::AddCoupling(block, ps.host, g.A_host.transpose() * h_xp);
      if (!fixed_[o.target]) NormalEquations::AddCoupling(block, o.target, g.A_target.transpose() * h_xp);
    }
    return energy;
  }

  Map* map_;
  PinholeCamera camera_;
  PbaOptions options_;
  std::vector<int> cams_;
  std::vector<bool> fixed_;
  std::vector<PointState> points_;
  std::vector<ErrorModel> models_;
  std::vector<PairGeometry> pairs_;
  std::vector<std::vector<PairAccumulator>> chunk_pairs_;
  std::vector<int> chunk_slots_;                              // Accumulators per chunk.
  std::vector<std::vector<std::pair<int, int>>> slot_chunks_;  // Per slot: (chunk, local index), chunk order.
  int num_obs_ = 0;
  int current_ = 0;  // Slot of the accepted linearisation in ObsState.
  int level_ = 0;
  PinholeCamera level_camera_;
};

}  // namespace

PbaSummary RunPba(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const PbaOptions& options,
                  const std::vector<int>& held, const PbaYield& yield) {
  const auto t0 = std::chrono::steady_clock::now();
  options.Validate();
  PbaSummary summary;
  Problem problem(map, camera, active, held, options);
  summary.keyframes = problem.NumCameras();
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
      const Problem::Backup backup = problem.Save();
      const Solution step = SolveSchur(eq, lambda);
      const bool converged = problem.Apply(step);
      const Problem::Trial trial = problem.LinearizeTrial(&trial_eq);
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
    summary.observations_removed = problem.MarkOutliers();
  }
  summary.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace dsm
