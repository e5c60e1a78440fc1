// SPDX-License-Identifier: MIT
// The final fit of a calibration: every parameter of the camera (fx fy cx cy and the model's
// distortion, camera.h) and every view's pose, by Levenberg-Marquardt (Ceres) on the corners'
// reprojection errors as dsm's own camera model projects them, from an initial solution; and the
// standard deviation of each camera parameter from the covariance at the solution (the corners'
// error taken as the residuals' RMS).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/lie/se3.h"

namespace dsm {

struct CornerView {
  std::vector<Eigen::Vector3d> board;  // The corners on the board ...
  std::vector<Eigen::Vector2d> image;  // ... and where they were detected.
};

struct RefinedCalibration {
  CameraCalibration camera;
  std::vector<SE3d> cam_from_board;
  // Of fx, fy, cx, cy, then each distortion parameter (empty when the covariance is singular: the
  // views leave some parameter unconstrained).
  std::vector<double> deviations;
};

RefinedCalibration RefineCalibration(const CameraCalibration& initial, const std::vector<SE3d>& cam_from_board,
                                     const std::vector<CornerView>& views);

}  // namespace dsm
