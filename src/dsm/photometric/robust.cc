// SPDX-License-Identifier: MIT
#include "dsm/photometric/robust.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <boost/math/distributions/students_t.hpp>

#include "dsm/util/check.h"
#include "dsm/util/median.h"
#include "dsm/util/nelder_mead.h"

namespace dsm {

namespace {

// log Gamma(x) without std::lgamma's write to the global `signgam` (a data race when the tracking
// and mapping threads both fit error models).
double LogGamma(double x) {
  int sign = 0;
  return lgamma_r(x, &sign);
}

constexpr double kMadToSigma = 1.4826;
constexpr double kMaxNu = 200.0;

// The degrees of freedom kept within [robust.min_nu, kMaxNu].
double ClampNu(double nu, const RobustOptions& options) { return std::clamp(nu, options.min_nu, kMaxNu); }

// Boost promotes double to long double by default (x87 arithmetic, several times slower); the fits
// call the t's CDF in every likelihood evaluation, and double is ample for them.
using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
using StudentT = boost::math::students_t_distribution<double, DoublePolicy>;

double TQuantileThreshold(double nu, double sigma, double quantile) {
  const StudentT dist(nu);
  return sigma * boost::math::quantile(dist, quantile);
}

// The residual magnitudes within `cut` (the core the t describes), and the t's starting nu from
// their kurtosis k: nu = (4k - 6)/(k - 3), the t's moment relation, with k >= 4 (4 < nu <= 10).
std::vector<float> CoreResiduals(const std::vector<double>& abs_r, double cut) {
  std::vector<float> kept;
  for (double a : abs_r)
    if (a <= cut) kept.push_back(static_cast<float>(a));
  return kept;
}

double NuFromKurtosis(const std::vector<float>& kept, const RobustOptions& options) {
  double m2 = 0.0, m4 = 0.0;
  for (float v : kept) {
    const double v2 = double(v) * v;
    m2 += v2;
    m4 += v2 * v2;
  }
  m2 /= kept.size();
  m4 /= kept.size();
  // All residuals zero (a uniform image against a uniform image): no tails to measure.
  if (!(m2 > 0.0)) return ClampNu(kMaxNu, options);
  const double kurtosis = std::max(m4 / (m2 * m2), 4.0);
  return ClampNu((4.0 * kurtosis - 6.0) / (kurtosis - 3.0), options);
}

// The t fitted to the residuals within min(3 sigma_MAD, R) as a sample of the t truncated there
// (robust.h).
ErrorModel FitTruncatedT(const std::vector<double>& abs_r, double mad_sigma, const RobustOptions& options,
                         ErrorModel m) {
  const double cut = std::min(3.0 * mad_sigma, options.gross_residual);
  const std::vector<float> kept = CoreResiduals(abs_r, cut);
  if (static_cast<int>(kept.size()) < options.min_residuals) return m;
  const double nu0 = NuFromKurtosis(kept, options);
  // The kept residuals are a sample of the t truncated to |r| <= cut: their likelihood is
  // normalised by the mass P(|r| <= cut) = 2 F(cut / sigma) - 1, so the cut tails do not bias nu.
  const double n_kept = static_cast<double>(kept.size());
  const auto nll = [&](const Eigen::VectorXd& x) {
    const double nu = ClampNu(std::exp(x(0)), options);
    const double sigma = std::exp(x(1));
    const double mass = 2.0 * boost::math::cdf(StudentT(nu), cut / sigma) - 1.0;
    return StudentTNegLogLikelihood(kept, nu, sigma) + n_kept * std::log(std::max(mass, 1e-300));
  };
  NelderMeadOptions nm;
  nm.tolerance = 1e-2;
  nm.max_iterations = 200;
  nm.initial_step = 0.3;
  const NelderMeadResult fit = NelderMead(nll, Eigen::Vector2d(std::log(nu0), std::log(mad_sigma)), nm);
  m.nu = ClampNu(std::exp(fit.x(0)), options);
  m.sigma = std::exp(fit.x(1));
  m.inlier_threshold = TQuantileThreshold(m.nu, m.sigma, options.inlier_quantile);
  m.fitted = true;
  return m;
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
  if (max_fit_samples < min_residuals) {
    throw InputError("max_fit_samples (pba., tracker.) must be at least " + std::to_string(min_residuals));
  }
  if (!(gross_residual >= 10.0)) throw InputError("robust.gross_residual must be at least 10");
  if (!(min_nu >= 1.0 && min_nu <= 100.0)) throw InputError("robust.min_nu must be within 1..100");
}

ErrorModel DefaultErrorModel(const RobustOptions& options) {
  ErrorModel m;
  m.kind = options.kind;
  m.huber_k = options.huber_threshold;
  m.inlier_threshold = options.kind == RobustKind::kStudentT ? TQuantileThreshold(m.nu, m.sigma, options.inlier_quantile)
                                                             : m.huber_k;
  return m;
}

void CapErrorModelScale(double max_sigma, ErrorModel* model) {
  if (model->kind != RobustKind::kStudentT || !(model->sigma > max_sigma)) return;
  const double f = max_sigma / model->sigma;
  model->sigma = max_sigma;
  model->inlier_threshold *= f;
}

double ErrorModelScaleCap(double max_ratio, const std::vector<uint8_t>& fitted, const std::vector<ErrorModel>& models) {
  std::vector<double> sigmas;
  for (size_t i = 0; i < models.size(); ++i)
    if (fitted[i]) sigmas.push_back(models[i].sigma);
  if (sigmas.size() < 3) return std::numeric_limits<double>::infinity();
  return max_ratio * Median(sigmas);
}

void BoundErrorModelScales(double max_ratio, const std::vector<uint8_t>& fitted, std::vector<ErrorModel>* models) {
  const double cap = ErrorModelScaleCap(max_ratio, fitted, *models);
  for (size_t i = 0; i < models->size(); ++i)
    if (fitted[i]) CapErrorModelScale(cap, &(*models)[i]);
}

double StudentTNegLogLikelihood(const std::vector<float>& r, double nu, double sigma) {
  const double n = static_cast<double>(r.size());
  const double log_norm = LogGamma(0.5 * (nu + 1.0)) - LogGamma(0.5 * nu) - 0.5 * std::log(nu * M_PI) - std::log(sigma);
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
    m.fitted = true;
    return m;
  }
  const ErrorModel fitted = FitTruncatedT(abs_r, mad_sigma, options, m);
  // A degenerate sample (e.g. a black frame) must not leave a model that poisons later sums.
  const bool finite = std::isfinite(fitted.nu) && std::isfinite(fitted.sigma) &&
                      std::isfinite(fitted.inlier_threshold) && fitted.sigma > 0.0;
  return finite ? fitted : m;
}

}  // namespace dsm
