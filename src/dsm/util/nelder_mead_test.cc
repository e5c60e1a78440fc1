// SPDX-License-Identifier: MIT
#include "dsm/util/nelder_mead.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(NelderMead, MinimisesRosenbrock) {
  const auto rosenbrock = [](const Eigen::VectorXd& x) {
    return 100.0 * std::pow(x(1) - x(0) * x(0), 2) + std::pow(1.0 - x(0), 2);
  };
  NelderMeadOptions options;
  options.tolerance = 1e-14;
  options.max_iterations = 2000;
  const auto r = NelderMead(rosenbrock, Eigen::Vector2d(-1.2, 1.0), options);
  EXPECT_NEAR(r.x(0), 1.0, 1e-4);
  EXPECT_NEAR(r.x(1), 1.0, 1e-4);
  EXPECT_LT(r.iterations, 2000);
}

}  // namespace
}  // namespace dsm
