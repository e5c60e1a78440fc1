// SPDX-License-Identifier: MIT
#include "dsm/optimization/normal_equations.h"

#include <Eigen/Cholesky>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "dsm/util/check.h"

namespace dsm {

void NormalEquations::Reset(const std::vector<bool>& fixed, int num_points) {
  num_cameras = static_cast<int>(fixed.size());
  block.assign(num_cameras, -1);
  int rows = 0;
  for (int c = 0; c < num_cameras; ++c) {
    if (fixed[c]) continue;
    block[c] = rows;
    rows += kCameraParams;
  }
  H_cc.setZero(rows, rows);
  b_c.setZero(rows);
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

Solution SolveSchur(const NormalEquations& eq, double lambda) {
  // S = H_cc - sum_p H_cp H_pp^-1 H_pc is formed in its lower block triangle only (and the
  // diagonal blocks whole): the LDLT below reads the lower triangle alone, and the upper blocks
  // were half of the work. Block rows are split between tasks; each sums its blocks over the
  // points in order, so S is the sequential loop's whatever the thread count.
  Eigen::MatrixXd S = eq.H_cc;
  S.diagonal() *= (1.0 + lambda);
  Eigen::VectorXd rhs = eq.b_c;
  std::vector<double> inv_hpp(eq.points.size(), 0.0);
  for (size_t i = 0; i < eq.points.size(); ++i) {
    const double hpp = eq.points[i].H_pp * (1.0 + lambda);
    if (hpp > 0.0) inv_hpp[i] = 1.0 / hpp;
  }
  const int block_rows = static_cast<int>(S.rows()) / kCameraParams;
  tbb::parallel_for(tbb::blocked_range<int>(0, block_rows), [&](const tbb::blocked_range<int>& rows) {
    const int first = rows.begin() * kCameraParams, end = rows.end() * kCameraParams;
    for (size_t i = 0; i < eq.points.size(); ++i) {
      if (inv_hpp[i] == 0.0) continue;
      const auto& p = eq.points[i];
      for (const auto& [ci, vi] : p.H_cp) {
        const int bi = eq.block[ci];
        if (bi < first || bi >= end) continue;  // Fixed (-1) or another task's row.
        rhs.segment<kCameraParams>(bi) -= vi * (p.b_p * inv_hpp[i]);
        for (const auto& [cj, vj] : p.H_cp) {
          const int bj = eq.block[cj];
          if (bj < 0 || bj > bi) continue;
          S.block<kCameraParams, kCameraParams>(bi, bj).noalias() -= vi * vj.transpose() * inv_hpp[i];
        }
      }
    }
  });
  Solution sol;
  sol.cameras.setZero(kCameraParams * eq.num_cameras);
  if (S.rows() > 0) {
    const Eigen::VectorXd x = Eigen::LDLT<Eigen::MatrixXd, Eigen::Lower>(S).solve(-rhs);
    for (int c = 0; c < eq.num_cameras; ++c)
      if (eq.block[c] >= 0) sol.cameras.segment<kCameraParams>(kCameraParams * c) = x.segment<kCameraParams>(eq.block[c]);
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

Solution SolveDense(const NormalEquations& eq, double lambda) {
  const int nc = static_cast<int>(eq.H_cc.rows());
  const int np = static_cast<int>(eq.points.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nc + np, nc + np);
  Eigen::VectorXd b(nc + np);
  H.topLeftCorner(nc, nc) = eq.H_cc;
  b.head(nc) = eq.b_c;
  for (int i = 0; i < np; ++i) {
    H(nc + i, nc + i) = eq.points[i].H_pp;
    b(nc + i) = eq.points[i].b_p;
    for (const auto& [c, v] : eq.points[i].H_cp) {
      if (eq.block[c] < 0) continue;
      H.block(eq.block[c], nc + i, kCameraParams, 1) += v;
      H.block(nc + i, eq.block[c], 1, kCameraParams) += v.transpose();
    }
  }
  H.diagonal() *= (1.0 + lambda);
  const Eigen::VectorXd x = H.ldlt().solve(-b);
  Solution sol;
  sol.cameras.setZero(kCameraParams * eq.num_cameras);
  for (int c = 0; c < eq.num_cameras; ++c)
    if (eq.block[c] >= 0) sol.cameras.segment<kCameraParams>(kCameraParams * c) = x.segment<kCameraParams>(eq.block[c]);
  sol.points = x.tail(np);
  return sol;
}

}  // namespace dsm
