// SPDX-License-Identifier: MIT
#include "dsm/geometry/umeyama.h"

#include <random>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

TEST(Umeyama, RecoversKnownSimilarity) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  Sim3d::Tangent xi;
  xi << 0.5, -1.0, 2.0, 0.3, -0.2, 0.9, std::log(2.5);
  const Sim3d truth = Sim3d::Exp(xi);
  std::vector<Eigen::Vector3d> x, y;
  for (int i = 0; i < 30; ++i) {
    x.emplace_back(n(rng), n(rng), n(rng));
    y.push_back(truth * x.back());
  }
  const Sim3d est = UmeyamaAlignment(x, y, true);
  EXPECT_NEAR(est.Scale(), 2.5, 1e-12);
  EXPECT_LT((est.Matrix() - truth.Matrix()).norm(), 1e-10);
  // Without scale the rotation is still exact for a pure similarity of centred data.
  const Sim3d rigid = UmeyamaAlignment(x, y, false);
  EXPECT_EQ(rigid.Scale(), 1.0);
  EXPECT_LT((rigid.Rotation() - truth.Rotation()).norm(), 1e-10);
}

TEST(Umeyama, HandlesReflectionCase) {
  // Planar points mirrored: the best proper rotation must still have det +1.
  std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  std::vector<Eigen::Vector3d> y{{0, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {-1, 1, 0}};
  const Sim3d est = UmeyamaAlignment(x, y, false);
  EXPECT_NEAR(est.Rotation().determinant(), 1.0, 1e-12);
}

TEST(Umeyama, RejectsTooFewPoints) {
  EXPECT_THROW(UmeyamaAlignment({{0, 0, 0}}, {{1, 1, 1}}, true), InputError);
}

}  // namespace
}  // namespace dsm
