// SPDX-License-Identifier: MIT
#include "dsm/geometry/umeyama.h"

#include <Eigen/SVD>

#include "dsm/util/check.h"

namespace dsm {

Sim3d UmeyamaAlignment(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                       bool with_scale) {
  DSM_CHECK(x.size() == y.size(), "point sets differ in size");
  const size_t n = x.size();
  if (n < 3) throw InputError("alignment needs at least 3 matched poses, got " + std::to_string(n));
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero(), mean_y = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= static_cast<double>(n);
  mean_y /= static_cast<double>(n);
  double sigma_x = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d dx = x[i] - mean_x;
    sigma_x += dx.squaredNorm();
    cov += (y[i] - mean_y) * dx.transpose();
  }
  sigma_x /= static_cast<double>(n);
  cov /= static_cast<double>(n);
  if (!(sigma_x > 0.0)) throw InputError("alignment is degenerate: all estimated positions coincide");

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixU() * S * svd.matrixV().transpose();
  const double c = with_scale ? (svd.singularValues().asDiagonal() * S).trace() / sigma_x : 1.0;
  const Eigen::Vector3d t = mean_y - c * R * mean_x;
  return Sim3d(c, SO3d(R), t);
}

}  // namespace dsm
