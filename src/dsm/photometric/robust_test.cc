// SPDX-License-Identifier: MIT
#include "dsm/photometric/robust.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace dsm {
namespace {

std::vector<float> SampleT(double nu, double sigma, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::student_t_distribution<double> t(nu);
  std::vector<float> r(n);
  for (float& v : r) v = static_cast<float>(sigma * t(rng));
  return r;
}

TEST(FitErrorModel, RecoversNuAndSigmaOfTSamples) {
  // The fit drops |r| > 3 sigma_MAD first (outlier protection) and models the truncation.
  for (const auto& [nu, sigma] : {std::pair{3.0, 4.0}, {5.0, 7.5}, {10.0, 2.0}}) {
    RobustOptions options;
    options.max_fit_samples = 20000;
    const ErrorModel m = FitErrorModel(SampleT(nu, sigma, 20000, 11), options);
    EXPECT_NEAR(m.sigma, sigma, 0.1 * sigma) << nu << " " << sigma;
    EXPECT_NEAR(std::log(m.nu), std::log(nu), 0.35) << nu << " " << sigma << " fitted nu " << m.nu;
    // The fitted t explains the samples better than the generating scale with a Gaussian-like nu.
    EXPECT_GT(m.inlier_threshold, 1.5 * m.sigma);
  }
}

TEST(FitErrorModel, FitBeatsTheStartingPoint) {
  const auto r = SampleT(4.0, 5.0, 5000, 3);
  RobustOptions options;
  options.max_fit_samples = 5000;
  const ErrorModel m = FitErrorModel(r, options);
  std::vector<float> kept;
  for (float v : r)
    if (std::abs(v) < 60) kept.push_back(v);
  EXPECT_LT(StudentTNegLogLikelihood(kept, m.nu, m.sigma), StudentTNegLogLikelihood(kept, 5.0, 7.5));
}

TEST(ErrorModel, WeightIsDerivativeOverResidual) {
  for (RobustKind kind : {RobustKind::kStudentT, RobustKind::kHuberFixed}) {
    ErrorModel m;
    m.kind = kind;
    m.nu = 4.0;
    m.sigma = 3.0;
    m.huber_k = 5.0;
    for (double r : {0.5, 2.0, 7.0, 30.0}) {
      // The energy is evaluated in single precision: a step well above its rounding.
      const double h = 1e-2;
      const double derivative = (m.Energy(r + h) - m.Energy(r - h)) / (2 * h);
      EXPECT_NEAR(m.Weight(r), derivative / r, 2e-3 * m.Weight(r) + 2e-4) << RobustKindName(kind) << " " << r;
    }
  }
}

TEST(FitErrorModel, MinNuBoundsTheTailsAndTheInlierThreshold) {
  // Cauchy samples (nu = 1): the free fit follows them to nu near 1 and a threshold of ~6 sigma;
  // with min_nu = 3 the fit stays at 3 and the threshold at the t(3) quantile (2.35 sigma).
  RobustOptions options;
  options.max_fit_samples = 20000;
  const std::vector<float> r = SampleT(1.0, 3.0, 20000, 7);
  const ErrorModel free = FitErrorModel(r, options);
  EXPECT_LT(free.nu, 1.5);
  EXPECT_GT(free.inlier_threshold, 5.0 * free.sigma);
  options.min_nu = 3.0;
  const ErrorModel floored = FitErrorModel(r, options);
  EXPECT_NEAR(floored.nu, 3.0, 1e-9);
  EXPECT_NEAR(floored.inlier_threshold / floored.sigma, 2.353, 1e-3);
  options.min_nu = 0.5;
  EXPECT_THROW(options.Validate(), std::exception);
}

TEST(FitErrorModel, HuberVariantsAndSmallSamples) {
  RobustOptions options;
  options.kind = RobustKind::kHuberMad;
  const ErrorModel mad = FitErrorModel(SampleT(50.0, 4.0, 5000, 5), options);
  EXPECT_NEAR(mad.sigma, 4.0, 0.4);
  EXPECT_NEAR(mad.huber_k, 1.345 * mad.sigma, 1e-12);
  options.kind = RobustKind::kHuberFixed;
  EXPECT_DOUBLE_EQ(FitErrorModel(SampleT(5.0, 4.0, 5000, 5), options).huber_k, 9.0);
  options.kind = RobustKind::kStudentT;
  const ErrorModel few = FitErrorModel(SampleT(5.0, 1.0, 20, 5), options);
  EXPECT_DOUBLE_EQ(few.sigma, 7.5);  // too few residuals: the default model
  EXPECT_THROW(ParseRobustKind("cauchy", "--robust"), std::exception);
}

TEST(FitErrorModel, UniformResidualsGiveAFiniteModel) {
  // A black frame against a black frame: every residual zero (or all alike).
  const RobustOptions options;
  for (const float value : {0.f, 3.f}) {
    const ErrorModel m = FitErrorModel(std::vector<float>(4000, value), options);
    EXPECT_TRUE(std::isfinite(m.nu) && std::isfinite(m.sigma) && m.sigma > 0.0) << value;
    EXPECT_TRUE(std::isfinite(m.inlier_threshold) && std::isfinite(m.Weight(1.0)) && std::isfinite(m.Energy(1.0)));
  }
}

TEST(CapErrorModelScale, BoundsSigmaAndScalesTheInlierThresholdWithIt) {
  ErrorModel m;
  m.nu = 1.5;
  m.sigma = 20.0;
  m.inlier_threshold = 90.0;
  CapErrorModelScale(5.0, &m);
  EXPECT_DOUBLE_EQ(m.sigma, 5.0);
  EXPECT_DOUBLE_EQ(m.nu, 1.5);
  EXPECT_DOUBLE_EQ(m.inlier_threshold, 22.5);
  // A scale within the bound and a Huber model are left as they are.
  ErrorModel within = m;
  CapErrorModelScale(8.0, &within);
  EXPECT_DOUBLE_EQ(within.sigma, 5.0);
  EXPECT_DOUBLE_EQ(within.inlier_threshold, 22.5);
  ErrorModel huber;
  huber.kind = RobustKind::kHuberFixed;
  huber.sigma = 20.0;
  CapErrorModelScale(5.0, &huber);
  EXPECT_DOUBLE_EQ(huber.sigma, 20.0);
}

TEST(BoundErrorModelScales, CapsFittedModelsAtARatioOfTheirMedianScale) {
  std::vector<ErrorModel> models(4);
  models[0].sigma = 2.0;
  models[1].sigma = 3.0;
  models[2].sigma = 20.0;
  models[2].inlier_threshold = 40.0;
  models[3].sigma = 50.0;  // Not fitted: neither counted nor capped.
  EXPECT_DOUBLE_EQ(ErrorModelScaleCap(3.0, {1, 1, 1, 0}, models), 9.0);
  BoundErrorModelScales(3.0, {1, 1, 1, 0}, &models);
  EXPECT_DOUBLE_EQ(models[0].sigma, 2.0);
  EXPECT_DOUBLE_EQ(models[1].sigma, 3.0);
  EXPECT_DOUBLE_EQ(models[2].sigma, 9.0);  // 3 x the median 3.
  EXPECT_DOUBLE_EQ(models[2].inlier_threshold, 18.0);
  EXPECT_DOUBLE_EQ(models[3].sigma, 50.0);
  // Fewer than three fitted models: no median to trust, nothing changes.
  std::vector<ErrorModel> two(2);
  two[0].sigma = 1.0;
  two[1].sigma = 30.0;
  EXPECT_TRUE(std::isinf(ErrorModelScaleCap(2.0, {1, 1}, two)));
  BoundErrorModelScales(2.0, {1, 1}, &two);
  EXPECT_DOUBLE_EQ(two[1].sigma, 30.0);
}

}  // namespace
}  // namespace dsm
