// SPDX-License-Identifier: MIT
// Nelder–Mead downhill simplex minimisation (gradient free), for small smooth problems such as
// fitting the two parameters of a t-distribution.
#pragma once

#include <functional>

#include <Eigen/Core>

namespace dsm {

struct NelderMeadOptions {
  int max_iterations = 200;
  double tolerance = 1e-2;  // Stop when the simplex's function values span less than this.
  double initial_step = 0.5;  // Size of the initial simplex along each axis.
};

struct NelderMeadResult {
  Eigen::VectorXd x;
  double value = 0.0;
  int iterations = 0;
};

NelderMeadResult NelderMead(const std::function<double(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x0,
                            const NelderMeadOptions& options = {});

}  // namespace dsm
