// SPDX-License-Identifier: MIT
// Normal equations of the photometric bundle adjustment and their solution by eliminating the
// points (Schur complement).
//
// Unknowns: x_c = 8 parameters per keyframe (pose increment 6, affine a, b) and x_p = one inverse
// depth per point. With damping D = lambda diag(H):
//
//   [ H_cc + D_cc   H_cp        ] [x_c]     [b_c]
//   [ H_pc          H_pp + D_pp ] [x_p] = - [b_p]
//
// H_pp is diagonal (a scalar per point), so eliminating the points is a division per point:
//
//   S   = H_cc + D_cc - sum_p H_cp(p) H_cp(p)^T / (H_pp(p) + D_pp(p))
//   rhs = b_c         - sum_p H_cp(p) b_p(p)    / (H_pp(p) + D_pp(p))
//   S x_c = -rhs,    x_p = -(b_p + H_cp^T x_c) / (H_pp + D_pp).
//
// H_cp(p) is non-zero only in the 8-blocks of the point's host and target keyframes.
//
// Fixed cameras are held at zero: their rows and columns drop out before the solve, so H_cc and
// b_c hold the free cameras only (most cameras of a window's problem are fixed, observed keyframes,
// and a dense 8n x 8n matrix over all of them would be zeroed and copied on every linearisation).
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace dsm {

constexpr int kCameraParams = 8;
using CameraVector = Eigen::Matrix<double, kCameraParams, 1>;

struct NormalEquations {
  int num_cameras = 0;
  std::vector<int> block;  // Per camera: the offset of its 8 rows in H_cc and b_c; -1 when fixed.
  Eigen::MatrixXd H_cc;  // 8f x 8f, f free cameras in camera order
  Eigen::VectorXd b_c;   // 8f
  struct PointBlock {
    double H_pp = 0.0;
    double b_p = 0.0;
    std::vector<std::pair<int, CameraVector>> H_cp;  // (camera index, 8 entries), one per camera
  };
  std::vector<PointBlock> points;

  // Zeroes the system of `fixed.size()` cameras (those with fixed[c] held at zero) and points.
  void Reset(const std::vector<bool>& fixed, int num_points);
  // H_cp of a point: adds `v` into the block of `camera`, merging repeated cameras.
  static void AddCoupling(PointBlock* point, int camera, const CameraVector& v);
};

struct Solution {
  Eigen::VectorXd cameras;  // 8n (every camera); zero for fixed cameras
  Eigen::VectorXd points;
};

// Solves the damped system by the Schur complement; fixed cameras get a zero step. Points with
// H_pp + D_pp <= 0 are left unchanged.
Solution SolveSchur(const NormalEquations& eq, double lambda);

// Reference: assembles and solves the full dense system (for tests).
Solution SolveDense(const NormalEquations& eq, double lambda);

}  // namespace dsm
