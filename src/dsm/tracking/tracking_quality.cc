// SPDX-License-Identifier: MIT
#include "dsm/tracking/tracking_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {

namespace {

std::string Format(const char* format, double a, double b) {
  char text[160];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

double MedianOf(const std::deque<double>& values) {
  if (values.empty()) return 0.0;
  return Median(std::vector<double>(values.begin(), values.end()));
}

}  // namespace

void QualityOptions::Validate() const {
  if (!(min_texture_ratio >= 0.0 && min_texture_ratio < 1.0)) throw InputError("quality.min_texture_ratio must be in [0, 1)");
  if (!(min_relocalisation_texture_ratio >= min_texture_ratio && min_relocalisation_texture_ratio <= 1.0))
    throw InputError("quality.min_relocalisation_texture_ratio must be in [quality.min_texture_ratio, 1]");
  if (!(max_residual_ratio > 1.0)) throw InputError("quality.max_residual_ratio must be above 1");
  if (!(max_relocalisation_residual_ratio >= max_residual_ratio))
    throw InputError("quality.max_residual_ratio must be at most the relocalisation's bound (6)");
  if (!(max_rotation_deg > 0.0 && max_rotation_deg <= 180.0)) throw InputError("quality.max_rotation_deg must be in (0, 180]");
  if (history < min_history) throw InputError("quality.history must be at least " + std::to_string(min_history));
}

TrackingQuality::TrackingQuality(const QualityOptions& options) : options_(options) { options_.Validate(); }

double TrackingQuality::ResidualLevel() const { return MedianOf(residual_); }
double TrackingQuality::TextureLevel() const { return MedianOf(texture_); }
double TrackingQuality::InlierLevel() const {
  return static_cast<int>(inliers_.size()) >= options_.min_history ? MedianOf(inliers_) : 0.0;
}

bool TrackingQuality::BelowTextureLevel(double texture, double ratio, double level) const {
  return static_cast<int>(texture_.size()) >= options_.min_history && texture < ratio * level;
}

std::string TrackingQuality::CheckImage(double texture) const {
  if (!std::isfinite(texture)) return "unusable image";
  if (BelowTextureLevel(texture, options_.min_texture_ratio, TextureLevel()))
    return Format("too little texture (%.2f, usual %.2f)", texture, TextureLevel());
  return {};
}

bool TrackingQuality::CheckKeyframeImage(double texture, double previous) const {
  return texture >= options_.min_keyframe_texture_step * previous;
}

std::string TrackingQuality::CheckRelocalisationImage(double texture, double keyframe_texture) const {
  const double level = keyframe_texture > 0.0 ? std::min(TextureLevel(), keyframe_texture) : TextureLevel();
  if (BelowTextureLevel(texture, options_.min_relocalisation_texture_ratio, level))
    return Format("less texture than usual (%.2f, usual %.2f)", texture, level);
  return {};
}

std::string TrackingQuality::CheckTracking(const TrackResult& r, const SE3d& step, int frames, double mean_idepth,
                                           bool other_keyframe) const {
  if (!r.ok) return r.reason;
  const double level = ResidualLevel();
  const double ratio = other_keyframe ? options_.max_relocalisation_residual_ratio : options_.max_residual_ratio;
  if (static_cast<int>(residual_.size()) >= options_.min_history && !(r.residual_p50 <= ratio * level))
    return Format("median residual %.1f, usual %.1f", r.residual_p50, level);
  if (r.inlier_ratio < options_.min_inlier_ratio)
    return Format("%.0f%% inliers (at least %.0f%%)", 100.0 * r.inlier_ratio, 100.0 * options_.min_inlier_ratio);
  const double deg = step.So3().Log().norm() * 180.0 / M_PI;
  if (deg > options_.max_rotation_deg * std::max(frames, 1))
    return Format("implausible motion (%.0f deg in %.0f frames)", deg, std::max(frames, 1));
  const double parallax = r.frame_from_keyframe.Translation().norm() * mean_idepth;
  if (!(parallax <= options_.max_parallax)) return Format("implausible motion (parallax %.2g, at most %.2g)", parallax, options_.max_parallax);
  return {};
}

std::string TrackingQuality::CheckSpeed(const SE3d& step, int frames, double speed, double mean_idepth) const {
  const double reach = std::max(frames, 1) * (options_.max_speed_ratio * speed + options_.min_speed / mean_idepth);
  const double moved = step.Translation().norm();
  if (!(moved <= reach)) return Format("implausible jump (%.2g, reach %.2g)", moved, reach);
  return {};
}

std::string TrackingQuality::CheckJump(const SE3d& step, int frames, const SE3d& velocity, double mean_idepth) const {
  const int n = std::max(frames, 1);
  std::string fail = CheckSpeed(step, n, velocity.Translation().norm(), mean_idepth);
  if (!fail.empty()) return fail;
  // The turn from the constant-velocity prediction, velocity^frames.
  const SO3d predicted = SO3d::Exp(velocity.So3().Log() * static_cast<double>(n));
  const double off_deg = (step.So3() * predicted.Inverse()).Log().norm() * 180.0 / M_PI;
  const double turn_reach = n * options_.min_turn_deg;
  if (!(off_deg <= turn_reach))
    return Format("implausible turn (%.0f deg off the prediction, reach %.0f deg)", off_deg, turn_reach);
  return {};
}

void TrackingQuality::Seed(double residual_p50, const std::vector<double>& textures) {
  residual_.clear();
  texture_.clear();
  if (residual_p50 > 0.0) residual_.assign(options_.min_history, residual_p50);
  for (double t : textures)
    if (std::isfinite(t)) texture_.push_back(t);
  while (static_cast<int>(texture_.size()) > options_.history) texture_.pop_front();
}

void TrackingQuality::Restart(double residual_p50, double texture) {
  const double level = std::max(ResidualLevel(), residual_p50);
  residual_.assign(options_.history, level);
  Trust(residual_p50, texture);
}

void TrackingQuality::Trust(double residual_p50, double texture, double inlier_ratio) {
  residual_.push_back(residual_p50);
  texture_.push_back(texture);
  if (inlier_ratio >= 0.0) inliers_.push_back(inlier_ratio);
  while (static_cast<int>(inliers_.size()) > options_.history) inliers_.pop_front();
  while (static_cast<int>(residual_.size()) > options_.history) residual_.pop_front();
  while (static_cast<int>(texture_.size()) > options_.history) texture_.pop_front();
}

}  // namespace dsm
