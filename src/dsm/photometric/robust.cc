// SPDX-License-Identifier: MIT
#include "dsm/photometric/robust.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <boost/math/distributions/students_t.hpp>

#include "dsm/util/check.h"
#include "dsm/util/nelder_mead.h"

namespace dsm {

namespace {

constexpr double kMadToSigma = 1.4826;
constexpr double kMinNu = 1.0, kMaxNu = 200.0;

double Median(std::vector<double> v) {
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

double TQuantileThreshold(double nu, double sigma, double quantile) {
  const boost::math::students_t dist(nu);
  return sigma * boost::math::quantile(dist, quantile);
}

}  // namespace

RobustKind ParseRobustKind(const std::string& name, const std::string& where) {
  if (name == "t") return RobustKind::kStudentT;
  if (name == "huber") return RobustKind::kHuberFixed;
  if (name == "huber-mad") return RobustKind::kHuberMad;
  throw InputError(where + ": unknown robust function '" + name + "' (expected t, huber or huber-mad)");
}

std::string RobustKindName(RobustKind kind) {
  switch (kind) {
    case RobustKind::kStudentT: return "t";
    case RobustKind::kHuberFixed: return "huber";
    case RobustKind::kHuberMad: return "huber-mad";
  }
  return "?";
}

void RobustOptions::Validate() const {
  if (!(huber_threshold > 0)) throw InputError("robust.huber_threshold must be positive");
  if (!(inlier_quantile > 0.5 && inlier_quantile < 1.0)) throw InputError("robust.inlier_quantile must be in (0.5, 1)");
  if (min_residuals < 10) throw InputError("robust.min_residuals must be at least 10");
  if (max_fit_samples < min_residuals) throw InputError("robust.max_fit_samples must be >= robust.min_residuals");
}

ErrorModel DefaultErrorModel(const RobustOptions& options) {
  ErrorModel m;
  m.kind = options.kind;
  m.huber_k = options.huber_threshold;
  m.inlier_threshold = options.kind == RobustKind::kStudentT ? TQuantileThreshold(m.nu, m.sigma, options.inlier_quantile)
                                                             : m.huber_k;
  return m;
}

double StudentTNegLogLikelihood(const std::vector<float>& r, double nu, double sigma) {
  const double n = static_cast<double>(r.size());
  const double log_norm = std::lgamma(0.5 * (nu + 1.0)) - std::lgamma(0.5 * nu) - 0.5 * std::log(nu * M_PI) - std::log(sigma);
  const float inv = static_cast<float>(1.0 / (nu * sigma * sigma));
  // Eight independent float partial sums of at most a few thousand terms each (vectorised),
  // added in double.
  constexpr size_t kLanes = 8;
  std::array<float, kLanes> lanes{};
  const size_t whole = r.size() - r.size() % kLanes;
  for (size_t i = 0; i < whole; i += kLanes)
    for (size_t j = 0; j < kLanes; ++j) lanes[j] += FastLog1p(r[i + j] * r[i + j] * inv);
  double sum = 0.0;
  for (float lane : lanes) sum += lane;
  for (size_t i = whole; i < r.size(); ++i) sum += FastLog1p(r[i] * r[i] * inv);
  return -n * log_norm + 0.5 * (nu + 1.0) * sum;
}

ErrorModel FitErrorModel(const std::vector<float>& residuals, const RobustOptions& options) {
  ErrorModel m = DefaultErrorModel(options);
  if (static_cast<int>(residuals.size()) < options.min_residuals) return m;
  // Evenly strided subset of at most max_fit_samples for the fit.
  const size_t max_samples = static_cast<size_t>(options.max_fit_samples);
  const size_t stride = (residuals.size() + max_samples - 1) / max_samples;
  std::vector<double> abs_r;
  for (size_t i = 0; i < residuals.size(); i += stride) abs_r.push_back(std::abs(residuals[i]));
  const double mad_sigma = std::max(1e-3, kMadToSigma * Median(abs_r));
  if (options.kind == RobustKind::kHuberFixed) return m;
  if (options.kind == RobustKind::kHuberMad) {
    m.sigma = mad_sigma;
    m.huber_k = 1.345 * mad_sigma;
    m.inlier_threshold = m.huber_k;
    return m;
  }
  const double cut = std::min(3.0 * mad_sigma, 60.0);
  std::vector<float> kept;
  for (double a : abs_r)
    if (a <= cut) kept.push_back(static_cast<float>(a));
  if (static_cast<int>(kept.size()) < options.min_residuals) return m;
  double m2 = 0.0, m4 = 0.0;
  for (float v : kept) {
    const double v2 = double(v) * v;
    m2 += v2;
    m4 += v2 * v2;
  }
  m2 /= kept.size();
  m4 /= kept.size();
  const double kurtosis = std::max(m4 / (m2 * m2), 4.0);
  const double nu0 = std::clamp((4.0 * kurtosis - 6.0) / (kurtosis - 3.0), kMinNu, kMaxNu);
  // The kept residuals are a sample of the t truncated to |r| <= cut: their likelihood is
  // normalised by the mass P(|r| <= cut) = 2 F(cut / sigma) - 1, so the cut tails do not bias nu.
  const double n_kept = static_cast<double>(kept.size());
  const auto nll = [&](const Eigen::VectorXd& x) {
    const double nu = std::clamp(std::exp(x(0)), kMinNu, kMaxNu);
    const double sigma = std::exp(x(1));
    const double mass = 2.0 * boost::math::cdf(boost::math::students_t(nu), cut / sigma) - 1.0;
    return StudentTNegLogLikelihood(kept, nu, sigma) + n_kept * std::log(std::max(mass, 1e-300));
  };
  NelderMeadOptions nm;
  nm.tolerance = 1e-2;
  nm.max_iterations = 200;
  nm.initial_step = 0.3;
  const NelderMeadResult fit = NelderMead(nll, Eigen::Vector2d(std::log(nu0), std::log(mad_sigma)), nm);
  m.nu = std::clamp(std::exp(fit.x(0)), kMinNu, kMaxNu);
  m.sigma = std::exp(fit.x(1));
  m.inlier_threshold = TQuantileThreshold(m.nu, m.sigma, options.inlier_quantile);
  return m;
}

}  // namespace dsm
