// SPDX-License-Identifier: MIT
// Robust error models of the photometric residuals (paper section V), one per keyframe, fitted to
// the gradient-weighted residuals r of all observations in that keyframe.
//
//   Student t (mu = 0):  rho(r) = (nu + 1)/2 log(1 + r^2 / (nu sigma^2)),  w(r) = (nu + 1) / (nu sigma^2 + r^2)
//   Huber:               rho(r) = r^2 / 2 (|r| < k), k |r| - k^2 / 2 (else),  w(r) = min(1, k / |r|)
//
// w = rho'(r) / r is the iteratively-reweighted least-squares weight.
//
// The fit (t): the residuals within 3 sigma_MAD (sigma_MAD = 1.4826 MAD, at most
// R = `gross_residual`) are a sample of the t truncated there; (nu, sigma) maximise their
// likelihood normalised by the kept mass 2 F(cut / sigma) - 1 (Nelder–Mead from
// nu = (4k - 6)/(k - 3), k = max(kurtosis, 4), and sigma_MAD).
// A pixel is an outlier when |r| exceeds the inlier threshold: the `inlier_quantile` quantile of
// the fitted t (times sigma, at most R), or k for Huber (the pixel masks of the PBA and the
// tracker).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dsm {

enum class RobustKind { kStudentT, kHuberFixed, kHuberMad };

RobustKind ParseRobustKind(const std::string& name, const std::string& where);  // t | huber | huber-mad
std::string RobustKindName(RobustKind kind);

struct RobustOptions {
  RobustKind kind = RobustKind::kStudentT;
  double huber_threshold = 9.0;   // Fixed Huber k, grey levels.
  double inlier_quantile = 0.95;  // Quantile of the fitted t that bounds inlier pixels.
  double gross_residual = 60.0;   // R: residuals beyond are outliers of any model (grey levels).
  double min_nu = 1.0;            // Lower bound of the fitted degrees of freedom.
  static constexpr int min_residuals = 100;  // Fewer residuals keep the default model.
  int max_fit_samples = 3000;     // The fit uses at most this many residuals (evenly strided).

  void Validate() const;  // Throws InputError naming the option.
};

struct ErrorModel {
  RobustKind kind = RobustKind::kStudentT;
  double nu = 5.0;      // t: degrees of freedom
  double sigma = 7.5;   // t: scale; Huber-MAD: 1.4826 MAD
  double huber_k = 9.0; // Huber threshold
  double inlier_threshold = 15.1;  // |r| above this marks an outlier pixel
  bool fitted = false;             // Fitted to residuals (false: the default model).

  double Weight(double r) const;  // Both inline below: the hottest calls of the system.
  double Energy(double r) const;
  bool IsOutlier(double r) const { return std::abs(r) > inlier_threshold; }
};

// log(1 + x) for x >= 0 to ~1e-6 relative: log(m 2^e) = e ln 2 + log(m), m in [1, 2), with
// log(m) = 2 atanh(z), z = (m - 1)/(m + 1) in [0, 1/3), by its odd series to z^9. Energies only
// rank LM steps.
inline float FastLog1p(float x) {
  const float y = 1.f + x;
  uint32_t bits;
  std::memcpy(&bits, &y, sizeof(bits));
  const int e = static_cast<int>((bits >> 23) & 0xFF) - 127;
  bits = (bits & 0x7FFFFFu) | 0x3F800000u;
  float m;
  std::memcpy(&m, &bits, sizeof(m));
  const float z = (m - 1.f) / (m + 1.f), z2 = z * z;
  const float series = z * (2.f + z2 * (2.f / 3.f + z2 * (2.f / 5.f + z2 * (2.f / 7.f + z2 * (2.f / 9.f)))));
  return static_cast<float>(e) * 0.69314718f + series;
}

inline double ErrorModel::Weight(double r) const {
  if (kind == RobustKind::kStudentT) return (nu + 1.0) / (nu * sigma * sigma + r * r);
  const double a = std::abs(r);
  return a < huber_k ? 1.0 : huber_k / a;
}

inline double ErrorModel::Energy(double r) const {
  if (kind == RobustKind::kStudentT) {
    return 0.5 * (nu + 1.0) * FastLog1p(static_cast<float>(r * r) * static_cast<float>(1.0 / (nu * sigma * sigma)));
  }
  const double a = std::abs(r);
  return a < huber_k ? 0.5 * r * r : huber_k * a - 0.5 * huber_k * huber_k;
}

// The default model of a new keyframe: t(nu = 5, sigma = 7.5) (or Huber with the fixed k).
ErrorModel DefaultErrorModel(const RobustOptions& options);

// Fits the model to residuals (see above). Deterministic.
ErrorModel FitErrorModel(const std::vector<float>& residuals, const RobustOptions& options);

// Bounds the t's scale: sigma <= max_sigma, its thresholds scaled with it (both are multiples of
// sigma for a given nu). Huber models are left as they are.
void CapErrorModelScale(double max_sigma, ErrorModel* model);

// max_ratio times the median scale of the fitted models (fitted[i] != 0; too few residuals keep
// the default model, which is not counted); infinity when fewer than three are fitted.
double ErrorModelScaleCap(double max_ratio, const std::vector<uint8_t>& fitted, const std::vector<ErrorModel>& models);

// Caps the scale of each fitted model at ErrorModelScaleCap.
void BoundErrorModelScales(double max_ratio, const std::vector<uint8_t>& fitted, std::vector<ErrorModel>* models);

// Negative log-likelihood of residuals under t(nu, 0, sigma).
double StudentTNegLogLikelihood(const std::vector<float>& residuals, double nu, double sigma);

}  // namespace dsm
