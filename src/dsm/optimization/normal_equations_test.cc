// SPDX-License-Identifier: MIT
#include "dsm/optimization/normal_equations.h"

#include <random>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// Normal equations J^T J, J^T r of random residuals, each touching one point, its host camera
// and one target camera: the structure of the PBA. Blocks of fixed cameras are left out.
NormalEquations RandomProblem(const std::vector<bool>& fixed, int points, uint32_t seed) {
  const int cameras = static_cast<int>(fixed.size());
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, cameras - 1);
  NormalEquations eq;
  eq.Reset(fixed, points);
  for (int p = 0; p < points; ++p) {
    const int host = pick(rng);
    for (int obs = 0; obs < 3; ++obs) {
      int target = pick(rng);
      if (target == host) target = (target + 1) % cameras;
      for (int k = 0; k < 8; ++k) {
        Eigen::Matrix<double, 17, 1> J;  // host 8, target 8, point 1
        for (int i = 0; i < 17; ++i) J(i) = n(rng);
        const double r = n(rng);
        const int cams[2] = {host, target};
        for (int a = 0; a < 2; ++a) {
          const int ra = eq.block[cams[a]];
          if (ra < 0) continue;
          eq.b_c.segment<8>(ra) += J.segment<8>(8 * a) * r;
          for (int b = 0; b < 2; ++b)
            if (eq.block[cams[b]] >= 0)
              eq.H_cc.block<8, 8>(ra, eq.block[cams[b]]) += J.segment<8>(8 * a) * J.segment<8>(8 * b).transpose();
          NormalEquations::AddCoupling(&eq.points[p], cams[a], J.segment<8>(8 * a) * J(16));
        }
        eq.points[p].H_pp += J(16) * J(16);
        eq.points[p].b_p += J(16) * r;
      }
    }
  }
  return eq;
}

TEST(NormalEquations, SchurSolveEqualsDenseSolve) {
  for (const double lambda : {0.0, 1e-3, 0.5}) {
    std::vector<bool> fixed(6, false);
    fixed[0] = fixed[3] = true;
    const NormalEquations eq = RandomProblem(fixed, 40, 17);
    ASSERT_EQ(eq.H_cc.rows(), 8 * 4);
    const Solution schur = SolveSchur(eq, lambda);
    const Solution dense = SolveDense(eq, lambda);
    EXPECT_LT((schur.cameras - dense.cameras).norm(), 1e-8 * (1 + dense.cameras.norm())) << lambda;
    EXPECT_LT((schur.points - dense.points).norm(), 1e-8 * (1 + dense.points.norm())) << lambda;
    EXPECT_EQ(schur.cameras.head<8>().norm(), 0.0);  // fixed cameras
    EXPECT_EQ(schur.cameras.segment<8>(24).norm(), 0.0);
    EXPECT_GT(schur.cameras.segment<8>(8).norm(), 0.0);
  }
}

TEST(NormalEquations, CouplingsMergePerCamera) {
  NormalEquations::PointBlock p;
  NormalEquations::AddCoupling(&p, 2, CameraVector::Ones());
  NormalEquations::AddCoupling(&p, 2, CameraVector::Ones());
  NormalEquations::AddCoupling(&p, 0, CameraVector::Ones());
  ASSERT_EQ(p.H_cp.size(), 2u);
  EXPECT_DOUBLE_EQ(p.H_cp[0].second(3), 2.0);
}

}  // namespace
}  // namespace dsm
