// SPDX-License-Identifier: MIT
// Least-squares similarity between two point sets (Umeyama 1991):
//   argmin_{c,R,t} sum_i || y_i - (c R x_i + t) ||^2.
//
//   mu_x, mu_y the means; sigma_x^2 = 1/n sum |x_i - mu_x|^2; Sigma = 1/n sum (y_i - mu_y)(x_i - mu_x)^T
//   Sigma = U D V^T;  S = diag(1, 1, det(U) det(V) < 0 ? -1 : 1)
//   R = U S V^T;  c = tr(D S) / sigma_x^2 (or 1 without scale);  t = mu_y - c R mu_x.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/lie/sim3.h"

namespace dsm {

// Returns y_from_x. Requires at least 3 points (throws InputError otherwise, and for degenerate sets).
Sim3d UmeyamaAlignment(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                       bool with_scale);

}  // namespace dsm
