// SPDX-License-Identifier: MIT
// The photometric residual of one point observation (paper eq. 1), on the 8-pixel pattern.
//
// A point lives in its host frame h at pixel u (pyramid level l) with inverse depth rho. Pattern
// pixel k sits at u_k = u + o_k and is seen in target frame t at
//   u'_k = pi( R q_k + t rho ),   q_k = K^-1 (u_k, 1),   (R, t) = target_from_host
// (pi is the pinhole projection; scaling the 3-D point by rho leaves u'_k unchanged). Its residual is
//   r_k = (I_h[u_k] - b_h) - s (I_t[u'_k] - b_t),    s = e^(a_h - a_t) tau_h / tau_t
// with tau the exposure times. Each residual is weighted by the gradient weight
//   w_g = c^2 / (c^2 + |grad I|^2)  (c^2 = 2500), averaged over host and target.
//
// Jacobians (p = R q_k + t rho, J_pi = d pi / d p at p):
//   d r / d u'    = -s grad I_t(u'_k)
//   d u' / d rho  = J_pi t
//   d u' / d xi   = J_pi [ rho I   -hat(p) ]   xi: left increment of target_from_host, (v, w)
//   d r / d a_h = -s (I_t - b_t),  d r / d a_t = s (I_t - b_t),  d r / d b_h = -1,  d r / d b_t = s
#pragma once

#include <array>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/image/pyramid.h"

namespace dsm {

constexpr int kPatternSize = 8;
// DSO's residual pattern (x, y offsets in pixels of the evaluated level).
constexpr std::array<std::array<int, 2>, kPatternSize> kPattern = {
    {{0, -2}, {-1, -1}, {1, -1}, {-2, 0}, {0, 0}, {2, 0}, {-1, 1}, {0, 2}}};
constexpr float kGradientWeightC2 = 2500.f;

inline float GradientWeight(float grad_sq) { return kGradientWeightC2 / (kGradientWeightC2 + grad_sq); }

using PatternSamples = std::array<float, kPatternSize>;

// The variance of a pattern's 8 values about their mean (summed in pattern order).
inline float PatternVariance(const PatternSamples& v) {
  float mean = 0.f;
  for (float x : v) mean += x;
  mean /= kPatternSize;
  float var = 0.f;
  for (float x : v) var += (x - mean) * (x - mean);
  return var / kPatternSize;
}

// Affine brightness of a frame: a (log gain) and b (offset), with its exposure time.
struct AffineBrightness {
  double a = 0.0;
  double b = 0.0;
};

// How the residuals of a map sample its images, host and target alike: bilinear interpolation, or
// the cubic B-spline approximation (ImagePyramid::SampleBSpline). On images with strong
// independent pixel noise (path-traced renders) bilinear interpolation averages the noise down by
// up to 4x half-way between pixels, so each residual's energy has a one-pixel ripple of the
// noise's variance that pulls every depth and pose; the B-spline's averaging hardly depends on
// the position (residual.cc). Its price: 4 x 4 pixels per sample instead of 2 x 2, and a blur.
enum class Interpolation { kBilinear, kBSpline };

// The host side of an observation at one pyramid level: its pattern intensities and gradient
// weights, sampled once per level.
struct HostPatch {
  Eigen::Vector2f center = Eigen::Vector2f::Zero();  // Pixel at the level.
  std::array<float, kPatternSize> value{};
  std::array<float, kPatternSize> weight_g{};  // Gradient weights w_g of the host pixels.
  Interpolation interpolation = Interpolation::kBilinear;  // Of the values, here and in the targets.
};

// Samples the host patch; false if the pattern leaves the image (border 1 px; 2 for the B-spline).
bool SampleHostPatch(const ImagePyramid& host, int level, const Eigen::Vector2f& center, Interpolation interpolation,
                     HostPatch* patch);

struct ObservationInput {
  const PinholeCamera* camera = nullptr;  // Camera of the level.
  const ImagePyramid* target = nullptr;
  int level = 0;
  Eigen::Matrix3f R;  // target_from_host
  Eigen::Vector3f t;
  float idepth = 1.f;
  AffineBrightness host_affine, target_affine;
  double host_exposure = 1.0, target_exposure = 1.0;
};

struct ObservationResiduals {
  std::array<float, kPatternSize> r;        // raw residuals
  std::array<float, kPatternSize> weight_g; // gradient weights
  Eigen::Vector2f center_target;            // projection of the patch centre in the target
  float target_depth = 0.f;                 // z of the point in the target frame
  // Jacobians (only when asked).
  Eigen::Matrix<float, kPatternSize, 6> J_pose;    // left increment of target_from_host
  Eigen::Matrix<float, kPatternSize, 1> J_idepth;
  Eigen::Matrix<float, kPatternSize, 4> J_affine;  // (a_h, b_h, a_t, b_t)
};

// Evaluates the 8 residuals and the derivatives asked for (kIdepth: J_idepth only, all a solve
// needs when both keyframes are fixed), sampling the target as the host patch was sampled; false
// when the point is behind the target or a pattern pixel falls outside it (border 2 px).
enum class Derivatives { kNone, kIdepth, kAll };
bool EvaluateObservation(const HostPatch& host, const ObservationInput& in, Derivatives derivatives,
                         ObservationResiduals* out);
inline bool EvaluateObservation(const HostPatch& host, const ObservationInput& in, bool jacobians,
                                ObservationResiduals* out) {
  return EvaluateObservation(host, in, jacobians ? Derivatives::kAll : Derivatives::kNone, out);
}

// s = e^(a_h - a_t) tau_h / tau_t
inline double BrightnessRatio(const AffineBrightness& host, const AffineBrightness& target, double host_exposure,
                              double target_exposure) {
  return std::exp(host.a - target.a) * host_exposure / target_exposure;
}

}  // namespace dsm
