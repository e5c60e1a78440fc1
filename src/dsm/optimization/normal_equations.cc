// SPDX-License-Identifier: MIT
#include "dsm/optimization/normal_equations.h"

#include <Eigen/Cholesky>

#include "dsm/util/check.h"

namespace dsm {

void NormalEquations::Reset(int cameras, int num_points) {
  num_cameras = cameras;
  H_cc.setZero(kCameraParams * cameras, kCameraParams * cameras);
  b_c.setZero(kCameraParams * cameras);
  // Keeps the coupling lists' storage across linearisations of the same problem.
  points.resize(num_points);
  for (PointBlock& p : points) {
    p.H_pp = 0.0;
    p.b_p = 0.0;
    p.H_cp.clear();
  }
}

void NormalEquations::AddCoupling(PointBlock* point, int camera, const CameraVector& v) {
  for (auto& [c, block] : point->H_cp) {
    if (c == camera) {
      block += v;
      return;
    }
  }
  point->H_cp.emplace_back(camera, v);
}

namespace {

// Indices of the free camera parameters.
std::vector<int> FreeIndices(int cameras, const std::vector<bool>& fixed) {
  std::vector<int> free;
  for (int c = 0; c < cameras; ++c)
    if (!fixed[c])
      for (int k = 0; k < kCameraParams; ++k) free.push_back(kCameraParams * c + k);
  return free;
}

}  // namespace

Solution SolveSchur(const NormalEquations& eq, double lambda, const std::vector<bool>& fixed) {
  DSM_CHECK(static_cast<int>(fixed.size()) == eq.num_cameras, "fixed flags per camera");
  const int n = kCameraParams * eq.num_cameras;
  Eigen::MatrixXd S = eq.H_cc;
  S.diagonal() *= (1.0 + lambda);
  Eigen::VectorXd rhs = eq.b_c;
  std::vector<double> inv_hpp(eq.points.size(), 0.0);
  for (size_t i = 0; i < eq.points.size(); ++i) {
    const auto& p = eq.points[i];
    const double hpp = p.H_pp * (1.0 + lambda);
    if (!(hpp > 0.0)) continue;
    inv_hpp[i] = 1.0 / hpp;
    // Blocks of fixed cameras are dropped from S below: skip them here (most of the cameras of a
    // window's problem are fixed, observed keyframes).
    for (const auto& [ci, vi] : p.H_cp) {
      if (fixed[ci]) continue;
      rhs.segment<kCameraParams>(kCameraParams * ci) -= vi * (p.b_p * inv_hpp[i]);
      for (const auto& [cj, vj] : p.H_cp) {
        if (fixed[cj]) continue;
        S.block<kCameraParams, kCameraParams>(kCameraParams * ci, kCameraParams * cj).noalias() -= vi * vj.transpose() * inv_hpp[i];
      }
    }
  }
  Solution sol;
  sol.cameras.setZero(n);
  const std::vector<int> free = FreeIndices(eq.num_cameras, fixed);
  if (!free.empty()) {
    const int m = static_cast<int>(free.size());
    Eigen::MatrixXd Sf(m, m);
    Eigen::VectorXd rf(m);
    for (int i = 0; i < m; ++i) {
      rf(i) = rhs(free[i]);
      for (int j = 0; j < m; ++j) Sf(i, j) = S(free[i], free[j]);
    }
    const Eigen::VectorXd xf = Sf.ldlt().solve(-rf);
    for (int i = 0; i < m; ++i) sol.cameras(free[i]) = xf(i);
  }
  sol.points.setZero(eq.points.size());
  for (size_t i = 0; i < eq.points.size(); ++i) {
    if (inv_hpp[i] == 0.0) continue;
    double coupled = eq.points[i].b_p;
    for (const auto& [c, v] : eq.points[i].H_cp) coupled += v.dot(sol.cameras.segment<kCameraParams>(kCameraParams * c));
    sol.points(i) = -coupled * inv_hpp[i];
  }
  return sol;
}

Solution SolveDense(const NormalEquations& eq, double lambda, const std::vector<bool>& fixed) {
  const int nc = kCameraParams * eq.num_cameras;
  const int np = static_cast<int>(eq.points.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nc + np, nc + np);
  Eigen::VectorXd b(nc + np);
  H.topLeftCorner(nc, nc) = eq.H_cc;
  b.head(nc) = eq.b_c;
  for (int i = 0; i < np; ++i) {
    H(nc + i, nc + i) = eq.points[i].H_pp;
    b(nc + i) = eq.points[i].b_p;
    for (const auto& [c, v] : eq.points[i].H_cp) {
      H.block(kCameraParams * c, nc + i, kCameraParams, 1) = v;
      H.block(nc + i, kCameraParams * c, 1, kCameraParams) = v.transpose();
    }
  }
  H.diagonal() *= (1.0 + lambda);
  std::vector<int> free = FreeIndices(eq.num_cameras, fixed);
  for (int i = 0; i < np; ++i) free.push_back(nc + i);
  const int m = static_cast<int>(free.size());
  Eigen::MatrixXd Hf(m, m);
  Eigen::VectorXd bf(m);
  for (int i = 0; i < m; ++i) {
    bf(i) = b(free[i]);
    for (int j = 0; j < m; ++j) Hf(i, j) = H(free[i], free[j]);
  }
  const Eigen::VectorXd xf = Hf.ldlt().solve(-bf);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(nc + np);
  for (int i = 0; i < m; ++i) x(free[i]) = xf(i);
  return {x.head(nc), x.tail(np)};
}

}  // namespace dsm
