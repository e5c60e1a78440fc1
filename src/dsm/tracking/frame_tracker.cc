// SPDX-License-Identifier: MIT
#include "dsm/tracking/frame_tracker.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "dsm/util/check.h"
#include "dsm/util/median.h"
#include "dsm/util/simd.h"

namespace dsm {

void TrackerOptions::Validate() const {
  if (levels < 1 || levels > 6) throw InputError("tracker.levels must be within 1..6");
  if (static_cast<int>(iterations.size()) < levels) throw InputError("tracker.iterations needs one count per level");
  for (int it : iterations)
    if (it < 1) throw InputError("tracker.iterations must be positive");
  if (!(min_usage > 0 && min_usage < 1)) throw InputError("tracker.min_usage must be in (0, 1)");
  robust.Validate();
}

FrameTracker::FrameTracker(const TrackerOptions& options) : options_(options) { options_.Validate(); }

void FrameTracker::SetReference(const ImagePyramid* keyframe, const PinholeCamera& camera,
                                const std::vector<ReferencePoint>& points) {
  points_ = points;
  levels_.assign(std::min(options_.levels, keyframe->levels()), LevelData{});
  double sum = 0.0;
  for (const auto& p : points) sum += p.idepth;
  mean_idepth_ = points.empty() ? 1.0 : sum / points.size();
  for (int l = 0; l < static_cast<int>(levels_.size()); ++l) {
    LevelData& level = levels_[l];
    level.camera = camera.AtLevel(l);
    const float fx = static_cast<float>(level.camera.fx), fy = static_cast<float>(level.camera.fy);
    const float cx = static_cast<float>(level.camera.cx), cy = static_cast<float>(level.camera.cy);
    const float scale = 1.f / static_cast<float>(1 << l);
    for (size_t i = 0; i < points.size(); ++i) {
      const float rho = points[i].idepth;
      const Eigen::Vector2f c((points[i].pixel.x() + 0.5f) * scale - 0.5f, (points[i].pixel.y() + 0.5f) * scale - 0.5f);
      for (int k = 0; k < kPatternSize; ++k) {
        const bool centre = kPattern[k][0] == 0 && kPattern[k][1] == 0;
        if (l >= kFirstCentreOnlyLevel && !centre) continue;
        const float x = c.x() + kPattern[k][0], y = c.y() + kPattern[k][1];
        if (!keyframe->InBounds(l, x, y, 1.f)) continue;
        const PixelGrad grad = keyframe->Sample(l, x, y);
        const Eigen::Vector3f q((x - cx) / fx, (y - cy) / fy, 1.f);
        const float w_g = GradientWeight(grad[1] * grad[1] + grad[2] * grad[2]);
        // d = J_pi^T grad at p = q / rho:  J_pi = [fx rho, 0, -fx qx rho; 0, fy rho, -fy qy rho]
        const Eigen::Vector3f d(grad[1] * fx * rho, grad[2] * fy * rho,
                                -(grad[1] * fx * q.x() + grad[2] * fy * q.y()) * rho);
        const Eigen::Vector3f p = q / rho;
        // Rotation part (p x d), written out: GCC 12 misreads Eigen's SSE cross product bounds.
        Vector8f g;
        g << d.x(), d.y(), d.z(), p.y() * d.z() - p.z() * d.y(), p.z() * d.x() - p.x() * d.z(),
            p.x() * d.y() - p.y() * d.x(), grad[0], 1.f;
        level.qx.push_back(q.x());
        level.qy.push_back(q.y());
        level.idepth.push_back(rho);
        level.grad_weight.push_back(w_g);
        level.sqrt_grad_weight.push_back(std::sqrt(w_g));
        level.g.push_back(g);
      }
    }
  }
}

namespace {

// Work split of the per-pixel loops: fixed, so that the sums do not depend on the threads.
constexpr size_t kChunk = 2048;
size_t NumChunks(size_t n) { return (n + kChunk - 1) / kChunk; }

using Vector8f = Eigen::Matrix<float, 8, 1>;
using Matrix8f = Eigen::Matrix<float, 8, 8>;

// The pose and camera of one evaluation, and the box [lo, x_hi) x [lo, y_hi) a pixel must land in
// (bilinear sampling 2 px inside the frame).
struct Projection {
  Eigen::Matrix3f R;
  Eigen::Vector3f t;
  float fx, fy, cx, cy;
  float lo, x_hi, y_hi;
  // A rolling shutter (ReadoutTurn): the turn vector w tau of level row v is v a + b.
  bool rolling = false;
  Eigen::Vector3f a = Eigen::Vector3f::Zero(), b = Eigen::Vector3f::Zero();
};

// Pixels [begin, end): p = R q + t rho (q_z = 1), u = pi(p); out-of-view pixels go to (lo, lo).
// kRolling: p is moved by the turn at the row it lands on, p + (v a + b) x p, and projected again.
// Inlined into each clone below, so that each is compiled for its target.
template <bool kRolling>
[[gnu::always_inline]] inline void ProjectPixelsAt(const Projection& pr, const float* qx, const float* qy,
                                                  const float* rho, size_t begin, size_t end, float* u, float* v,
                                                  float* valid) {
  const float R00 = pr.R(0, 0), R01 = pr.R(0, 1), R02 = pr.R(0, 2), R10 = pr.R(1, 0), R11 = pr.R(1, 1),
              R12 = pr.R(1, 2), R20 = pr.R(2, 0), R21 = pr.R(2, 1), R22 = pr.R(2, 2);
  const float tx = pr.t.x(), ty = pr.t.y(), tz = pr.t.z();
  const float ax = pr.a.x(), ay = pr.a.y(), az = pr.a.z(), bx = pr.b.x(), by = pr.b.y(), bz = pr.b.z();
#pragma omp simd
  for (size_t i = begin; i < end; ++i) {
    const float px = R00 * qx[i] + R01 * qy[i] + R02 + tx * rho[i];
    const float py = R10 * qx[i] + R11 * qy[i] + R12 + ty * rho[i];
    const float pz = R20 * qx[i] + R21 * qy[i] + R22 + tz * rho[i];
    float sx = px, sy = py, sz = pz;
    if constexpr (kRolling) {
      const float row = pr.fy * py / pz + pr.cy;
      const float wx = row * ax + bx, wy = row * ay + by, wz = row * az + bz;
      sx = px + (wy * pz - wz * py), sy = py + (wz * px - wx * pz), sz = pz + (wx * py - wy * px);
    }
    const float iz = 1.f / sz;
    const float ui = pr.fx * sx * iz + pr.cx, vi = pr.fy * sy * iz + pr.cy;
    // Bitwise: a short-circuit && is control flow, which keeps the loop from vectorising.
    const bool ok = (pz > 1e-6f) & (sz > 1e-6f) & (ui >= pr.lo) & (vi >= pr.lo) & (ui < pr.x_hi) & (vi < pr.y_hi);
    valid[i] = ok ? 1.f : 0.f;
    u[i] = ok ? ui : pr.lo;
    v[i] = ok ? vi : pr.lo;
  }
}

DSM_SIMD_CLONES void ProjectPixels(const Projection& pr, const float* qx, const float* qy, const float* rho,
                                   size_t begin, size_t end, float* u, float* v, float* valid) {
  ProjectPixelsAt<false>(pr, qx, qy, rho, begin, end, u, v, valid);
}

DSM_SIMD_CLONES void ProjectPixelsRolling(const Projection& pr, const float* qx, const float* qy, const float* rho,
                                          size_t begin, size_t end, float* u, float* v, float* valid) {
  ProjectPixelsAt<true>(pr, qx, qy, rho, begin, end, u, v, valid);
}

// r = I_f(u) - e^alpha I_r - beta at the projected pixels (0 where out of view).
DSM_SIMD_CLONES void SampleResiduals(const ImagePyramid& frame, int l, const float* u, const float* v,
                                     const float* valid, const Vector8f* g, float ea, float fb, size_t begin,
                                     size_t end, float* r) {
  for (size_t i = begin; i < end; ++i) r[i] = valid[i] * (frame.SampleValue(l, u[i], v[i]) - ea * g[i](6) - fb);
}

// The t's energy terms over the valid pixels: log(1 + rw^2 inv) and rw^2 (rw = sqrt(w_g) r), the
// count and how many lie beyond the threshold (rw^2 > t2).
struct EnergySums {
  double log_terms = 0.0, sum_sq = 0.0, bad = 0.0, count = 0.0;
};
DSM_SIMD_CLONES EnergySums SumTEnergy(const float* sw, const float* r, const float* valid, size_t n, float inv,
                                      float t2) {
  // Terms in single precision, sums in double (steps near convergence change the energy by less
  // than a float sum resolves), vectorised: the order of a SIMD reduction is fixed for a build.
  // The threshold test is the quiet comparison: `rw2 > t2` may trap (a signalling compare), so
  // GCC keeps it a branch and the whole loop scalar.
  double energy = 0.0, sum_sq = 0.0, bad = 0.0, count = 0.0;
#pragma omp simd reduction(+ : energy, sum_sq, bad, count)
  for (size_t i = 0; i < n; ++i) {
    const float rw = sw[i] * r[i], rw2 = rw * rw;
    sum_sq += rw2;
    energy += valid[i] * FastLog1p(rw2 * inv);
    bad += valid[i] * static_cast<float>(__builtin_isgreater(rw2, t2));
    count += valid[i];
  }
  return {energy, sum_sq, bad, count};
}

// sum_k w_k g_k g_k^T and sum_k w_k g_k r_k over pixels [begin, end), in single precision, with
// w_k = w_g w_rho(sqrt(w_g) r); the t's weight (nu + 1) / (nu sigma^2 + r^2) in single precision.
DSM_SIMD_CLONES void AccumulateSystem(const float* r, const float* valid, const float* grad_weight,
                                      const float* sqrt_grad_weight, const Vector8f* g, const ErrorModel& model,
                                      size_t begin, size_t end, Matrix8f* H, Vector8f* b) {
  const bool t = model.kind == RobustKind::kStudentT;
  const float nu1 = static_cast<float>(model.nu + 1.0), nus2 = static_cast<float>(model.nu * model.sigma * model.sigma);
  // Plain arrays, column j of H += (w g) g_j: Eigen's outer product is a call per pixel in a clone.
  alignas(32) float Hc[64] = {};
  alignas(32) float bc[8] = {};
  for (size_t i = begin; i < end; ++i) {
    if (valid[i] == 0.f) continue;
    const float rw = sqrt_grad_weight[i] * r[i];
    const float w = grad_weight[i] * (t ? nu1 / (nus2 + rw * rw) : static_cast<float>(model.Weight(rw)));
    const float* gi = g[i].data();
    alignas(32) float wg[8];
#pragma omp simd
    for (int k = 0; k < 8; ++k) wg[k] = w * gi[k];
    for (int j = 0; j < 8; ++j) {
#pragma omp simd
      for (int k = 0; k < 8; ++k) Hc[8 * j + k] += wg[k] * gi[j];
    }
#pragma omp simd
    for (int k = 0; k < 8; ++k) bc[k] += wg[k] * r[i];
  }
  *H = Eigen::Map<const Matrix8f>(Hc);
  *b = Eigen::Map<const Vector8f>(bc);
}

}  // namespace

void FrameTracker::Evaluate(int l, const ImagePyramid& frame, const SE3d& T, double alpha, double beta,
                            Residuals* out, const ReadoutTurn& turn) const {
  const LevelData& level = levels_[l];
  const Eigen::Matrix3f R = T.Rotation().cast<float>();
  const Eigen::Vector3f t = T.Translation().cast<float>();
  const float fx = static_cast<float>(level.camera.fx), fy = static_cast<float>(level.camera.fy);
  const float cx = static_cast<float>(level.camera.cx), cy = static_cast<float>(level.camera.cy);
  const float ea = static_cast<float>(std::exp(alpha)), fb = static_cast<float>(beta);
  const size_t n = level.qx.size();
  out->r.resize(n);
  out->valid.resize(n);
  out->u.resize(n);
  out->v.resize(n);
  Projection projection{R, t, fx, fy, cx, cy, 2.f, frame.width(l) - 3.f, frame.height(l) - 3.f};
  if (turn.line_delay_s > 0.0) {
    // Level row v is level-0 row v s + (s - 1) / 2, s = 2^l, seen at that row times the delay.
    const double s = 1 << l;
    projection.rolling = true;
    projection.a = (turn.angular_velocity * (turn.line_delay_s * s)).cast<float>();
    projection.b = (turn.angular_velocity * (turn.line_delay_s * 0.5 * (s - 1.0))).cast<float>();
  }
  const auto pass = [&](size_t begin, size_t end) {
    (projection.rolling ? ProjectPixelsRolling : ProjectPixels)(projection, level.qx.data(), level.qy.data(),
                                                                level.idepth.data(), begin, end, out->u.data(),
                                                                out->v.data(), out->valid.data());
    SampleResiduals(frame, l, out->u.data(), out->v.data(), out->valid.data(), level.g.data(), ea, fb, begin, end,
                    out->r.data());
  };
  if (n <= kChunk) return pass(0, n);
  tbb::parallel_for(size_t{0}, NumChunks(n), [&](size_t c) { pass(c * kChunk, std::min(n, (c + 1) * kChunk)); });
}

FrameTracker::Energy FrameTracker::SumEnergy(int l, const Residuals& res, const ErrorModel& model) const {
  const LevelData& level = levels_[l];
  const size_t n = res.r.size();
  const float* r = res.r.data();
  const float* valid = res.valid.data();
  const float* sw = level.sqrt_grad_weight.data();
  const float threshold = static_cast<float>(model.inlier_threshold);
  double energy = 0.0, sum_sq = 0.0, bad = 0.0, count = 0.0;
  if (model.kind == RobustKind::kStudentT) {
    // rho(rw) = (nu + 1)/2 log(1 + rw^2 / (nu sigma^2)): the logs summed, the factor applied once.
    const float inv = static_cast<float>(1.0 / (model.nu * model.sigma * model.sigma));
    const EnergySums sums = SumTEnergy(sw, r, valid, n, inv, threshold * threshold);
    energy = sums.log_terms, sum_sq = sums.sum_sq, bad = sums.bad, count = sums.count;
    energy *= 0.5 * (model.nu + 1.0);
  } else {
    for (size_t i = 0; i < n; ++i) {
      const float rw = sw[i] * r[i];
      sum_sq += rw * rw;
      energy += valid[i] * static_cast<float>(model.Energy(rw));
      bad += valid[i] * (std::abs(rw) > threshold ? 1.f : 0.f);
      count += valid[i];
    }
  }
  Energy e;
  e.energy = energy;
  e.sum_sq = sum_sq;
  e.valid = static_cast<int>(count);
  e.bad = static_cast<int>(bad);
  return e;
}

FrameTracker::System8 FrameTracker::SumSystem(int l, const Residuals& res, const ErrorModel& model,
                                              double alpha) const {
  const LevelData& level = levels_[l];
  const size_t n = res.r.size();
  // sum_k w_k g_k g_k^T and sum_k w_k g_k r_k per chunk, in single precision.
  std::vector<Matrix8f, Eigen::aligned_allocator<Matrix8f>> H(NumChunks(n));
  std::vector<Vector8f, Eigen::aligned_allocator<Vector8f>> b(NumChunks(n));
  const auto pass = [&](size_t c) {
    AccumulateSystem(res.r.data(), res.valid.data(), level.grad_weight.data(), level.sqrt_grad_weight.data(),
                     level.g.data(), model, c * kChunk, std::min(n, (c + 1) * kChunk), &H[c], &b[c]);
  };
  if (n <= kChunk) {
    if (n > 0) pass(0);
  } else {
    tbb::parallel_for(size_t{0}, NumChunks(n), pass);
  }
  System8 sys;
  for (size_t c = 0; c < H.size(); ++c) {
    sys.H += H[c].cast<double>();
    sys.b += b[c].cast<double>();
  }
  // H = D S D, b = -D s with D = diag(e^alpha (x7), 1).
  Eigen::Matrix<double, 8, 1> D = Eigen::Matrix<double, 8, 1>::Constant(std::exp(alpha));
  D(7) = 1.0;
  sys.H = D.asDiagonal() * sys.H * D.asDiagonal();
  sys.b = -(D.asDiagonal() * sys.b);
  return sys;
}

FrameTracker::Energy FrameTracker::CoarseSum(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta,
                                             const ErrorModel& model) const {
  const int l = static_cast<int>(levels_.size()) - 1;
  Residuals res;
  Evaluate(l, frame, guess, alpha, beta, &res);
  return SumEnergy(l, res, model);
}

double FrameTracker::CoarseEnergy(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta) const {
  const Energy e = CoarseSum(frame, guess, alpha, beta, DefaultErrorModel(options_.robust));
  if (e.valid < 0.5 * levels_.back().qx.size()) return std::numeric_limits<double>::infinity();
  return e.Mean();
}

double FrameTracker::CoarseEnergyOverAll(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta) const {
  const size_t n = levels_.back().qx.size();
  if (n == 0) return std::numeric_limits<double>::infinity();
  const ErrorModel model = DefaultErrorModel(options_.robust);
  const Energy e = CoarseSum(frame, guess, alpha, beta, model);
  return (e.energy + static_cast<double>(n - e.valid) * model.Energy(model.inlier_threshold)) / n;
}

TrackResult FrameTracker::Track(const ImagePyramid& frame, const SE3d& guess, double alpha_guess,
                                double beta_guess, int frames, const ReadoutTurn& turn) const {
  TrackResult r = TrackOnce(frame, guess, alpha_guess, beta_guess, /*hold_brightness=*/false, turn);
  const int steps = std::clamp(frames, 1, options_.max_alpha_frames);
  if (!r.ok || std::abs(r.alpha - alpha_guess) <= options_.max_alpha_step * steps) return r;
  TrackResult held = TrackOnce(frame, guess, alpha_guess, beta_guess, /*hold_brightness=*/true, turn);
  held.brightness_held = true;
  held.iterations += r.iterations;
  return held;
}

TrackResult FrameTracker::TrackOnce(const ImagePyramid& frame, const SE3d& guess, double alpha_guess,
                                    double beta_guess, bool hold_brightness, const ReadoutTurn& turn) const {
  TrackResult result;
  result.frame_from_keyframe = guess;
  result.alpha = alpha_guess;
  result.beta = beta_guess;
  if (points_.empty()) {
    result.reason = "no reference points";
    return result;
  }
  SE3d T = guess;
  double alpha = alpha_guess, beta = beta_guess;
  ErrorModel model = DefaultErrorModel(options_.robust);
  Residuals res, trial;
  std::vector<float> weighted;
  for (int l = static_cast<int>(levels_.size()) - 1; l >= 0; --l) {
    const LevelData& level = levels_[l];
    Evaluate(l, frame, T, alpha, beta, &res, turn);
    weighted.clear();
    for (size_t i = 0; i < res.r.size(); ++i)
      if (res.valid[i] != 0.f) weighted.push_back(level.sqrt_grad_weight[i] * res.r[i]);
    model = FitErrorModel(weighted, options_.robust);
    Energy energy = SumEnergy(l, res, model);
    System8 sys = SumSystem(l, res, model, alpha);
    double lambda = 1e-3;
    for (int it = 0; it < options_.iterations[l]; ++it) {
      ++result.iterations;
      if (energy.valid < 10) break;
      Eigen::Matrix<double, 8, 8> H = sys.H;
      H.diagonal() *= (1.0 + lambda);
      Eigen::Matrix<double, 8, 1> delta = Eigen::Matrix<double, 8, 1>::Zero();
      if (hold_brightness) {
        delta.head<6>() = H.topLeftCorner<6, 6>().ldlt().solve(-sys.b.head<6>());
      } else {
        delta = H.ldlt().solve(-sys.b);
      }
      if (!delta.allFinite()) break;
      const SE3d T_new = T * SE3d::Exp(delta.head<6>()).Inverse();
      const double alpha_new = alpha + delta(6), beta_new = beta + delta(7);
      const double f = std::max(level.camera.fx, level.camera.fy);
      const bool small = delta.segment<3>(3).norm() * f + delta.head<3>().norm() * f * mean_idepth_ <
                             options_.convergence_px &&
                         std::abs(delta(6)) < 1e-4;
      Evaluate(l, frame, T_new, alpha_new, beta_new, &trial, turn);
      const Energy next = SumEnergy(l, trial, model);
      // Compare mean energies so that pixels leaving the image do not look like progress.
      const bool better = next.valid > 0 && next.Mean() < energy.Mean() && next.valid >= 0.9 * energy.valid;
      if (better) {
        T = T_new, alpha = alpha_new, beta = beta_new, energy = next;
        std::swap(res, trial);
        if (!small) sys = SumSystem(l, res, model, alpha);
        lambda = std::max(lambda * 0.5, 1e-6);
      } else {
        lambda *= 4.0;
        if (lambda > 1e3) break;
      }
      if (small) break;
    }
    if (l == 0 && energy.valid > 0) {
      result.inlier_ratio = 1.0 - static_cast<double>(energy.bad) / energy.valid;
      result.rmse = std::sqrt(energy.sum_sq / energy.valid);
      weighted.clear();
      for (size_t i = 0; i < res.r.size(); ++i)
        if (res.valid[i] != 0.f) weighted.push_back(std::abs(level.sqrt_grad_weight[i] * res.r[i]));
      result.residual_p50 = Median(weighted);
    }
  }
  result.frame_from_keyframe = T;
  result.alpha = alpha;
  result.beta = beta;
  result.model = model;
  // Usage and visibility from the point centres at level 0.
  const PinholeCamera& cam = levels_[0].camera;
  const Eigen::Matrix3d R = T.Rotation();
  int usable = 0;
  double visibility = 0.0;
  for (const ReferencePoint& p : points_) {
    const Eigen::Vector3d q = cam.Unproject(p.pixel.x(), p.pixel.y());
    const Eigen::Vector3d ps = R * q + T.Translation() * p.idepth;  // = rho p_frame
    if (ps.z() <= 0) continue;
    const Eigen::Vector2d u = cam.Project(ps);
    if (!frame.InBounds(0, static_cast<float>(u.x()), static_cast<float>(u.y()), 4.f)) continue;
    ++usable;
    visibility += std::min(ps.z(), 1.0);  // rho_kf / rho_frame, capped at 1
  }
  result.usage = static_cast<double>(usable) / points_.size();
  result.visibility = visibility / points_.size();
  if (!T.Matrix().allFinite() || !std::isfinite(alpha)) {
    result.reason = "diverged";
  } else if (result.usage < options_.min_usage) {
    result.reason = "too few points in view (" + std::to_string(static_cast<int>(100 * result.usage)) + "%)";
  } else {
    result.ok = true;
  }
  return result;
}

}  // namespace dsm
