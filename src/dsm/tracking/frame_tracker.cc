// SPDX-License-Identifier: MIT
#include "dsm/tracking/frame_tracker.h"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "dsm/util/check.h"

namespace dsm {

void TrackerOptions::Validate() const {
  if (levels < 1 || levels > 6) throw InputError("tracker.levels must be within 1..6");
  if (static_cast<int>(iterations.size()) < levels) throw InputError("tracker.iterations needs one count per level");
  for (int it : iterations)
    if (it < 1) throw InputError("tracker.iterations must be positive");
  if (!(min_usage > 0 && min_usage < 1)) throw InputError("tracker.min_usage must be in (0, 1)");
  if (!(convergence_px > 0 && convergence_px < 1)) throw InputError("tracker.convergence_px must be in (0, 1)");
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
        const PixelGrad g = keyframe->Sample(l, x, y);
        LevelPoint lp;
        lp.q = Eigen::Vector3f((x - cx) / fx, (y - cy) / fy, 1.f);
        lp.idepth = rho;
        lp.ref_value = g[0];
        lp.grad_weight = GradientWeight(g[1] * g[1] + g[2] * g[2]);
        // d = J_pi^T grad at p = q / rho:  J_pi = [fx rho, 0, -fx qx rho; 0, fy rho, -fy qy rho]
        const Eigen::Vector3f d(g[1] * fx * rho, g[2] * fy * rho, -(g[1] * fx * lp.q.x() + g[2] * fy * lp.q.y()) * rho);
        const Eigen::Vector3f p = lp.q / rho;
        // Rotation part (p x d), written out: GCC 12 misreads Eigen's SSE cross product bounds.
        lp.J_geo << d.x(), d.y(), d.z(), p.y() * d.z() - p.z() * d.y(), p.z() * d.x() - p.x() * d.z(),
            p.x() * d.y() - p.y() * d.x();
        level.points.push_back(lp);
        level.owner.push_back(static_cast<int>(i));
      }
    }
  }
}

FrameTracker::Accumulated FrameTracker::Evaluate(int l, const ImagePyramid& frame, const SE3d& T, double alpha,
                                                 double beta, const ErrorModel& model, bool jacobians,
                                                 std::vector<float>* residuals) const {
  const LevelData& level = levels_[l];
  const Eigen::Matrix3f R = T.Rotation().cast<float>();
  const Eigen::Vector3f t = T.Translation().cast<float>();
  const float fx = static_cast<float>(level.camera.fx), fy = static_cast<float>(level.camera.fy);
  const float cx = static_cast<float>(level.camera.cx), cy = static_cast<float>(level.camera.cy);
  const float ea = static_cast<float>(std::exp(alpha)), fb = static_cast<float>(beta);
  // Pass 1, in parallel: projection, sampling and robust energy per pixel (the memory-bound part).
  // Pass 2, in pixel order: the sums, exactly those of a sequential loop whatever the threads.
  struct PixelResult {
    bool valid = false;
    float r = 0.f;
    double rw = 0.0, energy = 0.0;
  };
  const size_t n = level.points.size();
  std::vector<PixelResult> pixels(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const LevelPoint& lp = level.points[i];
      const Eigen::Vector3f p = R * lp.q + t * lp.idepth;
      if (!(p.z() > 1e-6f)) continue;
      const float u = fx * p.x() / p.z() + cx, v = fy * p.y() / p.z() + cy;
      if (!frame.InBounds(l, u, v, 2.f)) continue;
      PixelResult& out = pixels[i];
      out.valid = true;
      out.r = frame.SampleValue(l, u, v) - ea * lp.ref_value - fb;
      out.rw = std::sqrt(lp.grad_weight) * out.r;
      out.energy = model.Energy(out.rw);
    }
  });
  Accumulated acc;
  Eigen::Matrix<double, 8, 1> J;
  for (size_t i = 0; i < n; ++i) {
    const PixelResult& px = pixels[i];
    if (!px.valid) continue;
    const LevelPoint& lp = level.points[i];
    if (residuals) residuals->push_back(static_cast<float>(px.rw));
    acc.energy += px.energy;
    acc.bad += model.IsOutlier(px.rw);
    ++acc.valid;
    if (!jacobians) continue;
    const double w = lp.grad_weight * model.Weight(px.rw);
    J << (-ea * lp.J_geo).cast<double>().transpose(), -ea * lp.ref_value, -1.0;
    // Upper triangle only; mirrored after the loop.
    for (int a = 0; a < 8; ++a) {
      const double wja = w * J(a);
      for (int b = a; b < 8; ++b) acc.H(a, b) += wja * J(b);
      acc.b(a) += wja * px.r;
    }
  }
  acc.H.triangularView<Eigen::StrictlyLower>() = acc.H.transpose();
  return acc;
}

double FrameTracker::CoarseEnergy(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta) const {
  const int l = static_cast<int>(levels_.size()) - 1;
  const ErrorModel model = DefaultErrorModel(options_.robust);
  const Accumulated acc = Evaluate(l, frame, guess, alpha, beta, model, false, nullptr);
  if (acc.valid < 0.5 * levels_[l].points.size()) return std::numeric_limits<double>::infinity();
  return acc.energy / acc.valid;
}

TrackResult FrameTracker::Track(const ImagePyramid& frame, const SE3d& guess, double alpha_guess,
                                double beta_guess) const {
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
  for (int l = static_cast<int>(levels_.size()) - 1; l >= 0; --l) {
    std::vector<float> residuals;
    Evaluate(l, frame, T, alpha, beta, DefaultErrorModel(options_.robust), false, &residuals);
    model = FitErrorModel(residuals, options_.robust);
    Accumulated acc = Evaluate(l, frame, T, alpha, beta, model, true, nullptr);
    double lambda = 1e-3;
    for (int it = 0; it < options_.iterations[l]; ++it) {
      ++result.iterations;
      if (acc.valid < 10) break;
      Eigen::Matrix<double, 8, 8> H = acc.H;
      H.diagonal() *= (1.0 + lambda);
      const Eigen::Matrix<double, 8, 1> delta = H.ldlt().solve(-acc.b);
      if (!delta.allFinite()) break;
      const SE3d T_new = T * SE3d::Exp(delta.head<6>()).Inverse();
      const double alpha_new = alpha + delta(6), beta_new = beta + delta(7);
      const double f = std::max(levels_[l].camera.fx, levels_[l].camera.fy);
      const bool small = delta.segment<3>(3).norm() * f + delta.head<3>().norm() * f * mean_idepth_ <
                             options_.convergence_px &&
                         std::abs(delta(6)) < 1e-4;
      const Accumulated next = Evaluate(l, frame, T_new, alpha_new, beta_new, model, true, nullptr);
      // Compare mean energies so that pixels leaving the image do not look like progress.
      const bool better = next.valid > 0 && next.energy / next.valid < acc.energy / std::max(acc.valid, 1) &&
                          next.valid >= 0.9 * acc.valid;
      if (better) {
        T = T_new, alpha = alpha_new, beta = beta_new, acc = next;
        lambda = std::max(lambda * 0.5, 1e-6);
      } else {
        lambda *= 4.0;
        if (lambda > 1e3) break;
      }
      if (small) break;
    }
    if (l == 0) {
      std::vector<float> final_residuals;
      const Accumulated last = Evaluate(0, frame, T, alpha, beta, model, false, &final_residuals);
      result.inlier_ratio = last.valid > 0 ? 1.0 - static_cast<double>(last.bad) / last.valid : 0.0;
      double sum_sq = 0.0;
      for (float r : final_residuals) sum_sq += double(r) * r;
      result.rmse = final_residuals.empty() ? 0.0 : std::sqrt(sum_sq / final_residuals.size());
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
