// SPDX-License-Identifier: MIT
// The hot path of the bundle adjustment: one pass over the observations, each evaluated at the
// current state and added into its host-target pair's normal equations.
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/optimization/pba_problem.h"
#include "dsm/util/simd.h"

namespace dsm::internal {
namespace {

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

}  // namespace

Problem::Trial Problem::LinearizeTrial(NormalEquations* eq) {
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

bool Problem::Evaluate(const PointState& ps, const ObsState& o, Derivatives derivatives,
                       ObservationResiduals* res) const {
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

// Robust energy of the 8 pixels given sqrt(w_g) per pixel; counts pixels above the inlier
// threshold into *bad. The t-distribution's is computed lane-wise (vectorised) with the values
// ErrorModel::Energy gives, summed in pixel order.
double Problem::PixelEnergy(const PatternValues& residuals, const PatternValues& sqrt_weight_g, const ErrorModel& model,
                            int* bad) {
  double e = 0.0;
  int n_bad = 0;
  if (model.kind == RobustKind::kStudentT) {
    alignas(32) float log_terms[kPatternSize];
    alignas(32) int outlier[kPatternSize];
    const float inv = static_cast<float>(1.0 / (model.nu * model.sigma * model.sigma));
    // |r| > threshold (double) for a float |r|: |r| > the largest float at most the threshold (no
    // float lies between the two). In float and by the quiet comparison the loop vectorises; in
    // double, or by `>` (which may trap, so GCC keeps it a branch), it ran one pixel at a time.
    float threshold = static_cast<float>(model.inlier_threshold);
    if (static_cast<double>(threshold) > model.inlier_threshold) threshold = std::nextafter(threshold, -INFINITY);
    const float* r_k = residuals.data();
    const float* s_k = sqrt_weight_g.data();
#pragma omp simd
    for (int k = 0; k < kPatternSize; ++k) {
      const float r = s_k[k] * r_k[k];
      log_terms[k] = FastLog1p(r * r * inv);
      outlier[k] = __builtin_isgreater(std::abs(r), threshold);
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

PatternValues Problem::SqrtOf(const PatternValues& v) {
  PatternValues out;
#pragma omp simd
  for (int k = 0; k < kPatternSize; ++k) out[k] = std::sqrt(v[k]);
  return out;
}

// Linearises point i's observations into the trial slot (returns their energy) and adds their
// energy on the accepted slot's set and weights to *judged.
double Problem::LinearizePoint(size_t i, std::vector<PairAccumulator>* pairs, NormalEquations::PointBlock* block,
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
    o.texture_lost[trial] = TextureLostAtLevel(ps, res);
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
    if (!ps.frozen) {  // A frozen point's H_pp stays 0: SolveSchur leaves its depth alone.
      block->H_pp += Jr.dot(w.asDiagonal() * Jr);
      block->b_p += Jr.dot(w.asDiagonal() * r);
    }
    if (g.slot < 0) continue;
    // Camera blocks and the point's coupling to the free keyframes (a fixed one's would be
    // dropped by the Schur complement and multiply a zero step in the back-substitution).
    Eigen::Matrix<double, kPatternSize, 10> Jx;
    Jx << res.J_pose.cast<double>(), res.J_affine.cast<double>();
    PairAccumulator& acc = (*pairs)[o.acc];
    Vector10 h_xp;
    AccumulateObservation(Jx.data(), w.data(), r.data(), Jr.data(), acc.H.data(), acc.b.data(), h_xp.data());
    if (ps.frozen) continue;
    if (!fixed_[ps.host]) NormalEquations::AddCoupling(block, ps.host, g.A_host.transpose() * h_xp);
    if (!fixed_[o.target]) NormalEquations::AddCoupling(block, o.target, g.A_target.transpose() * h_xp);
  }
  return energy;
}

}  // namespace dsm::internal
