// SPDX-License-Identifier: MIT
#include "dsm/calibration/refine.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

namespace dsm {

namespace {

// One corner's reprojection error; parameters: [fx fy cx cy], the distortion (when the model has
// any) and the view's pose [angle-axis, translation] (cam_from_board).
struct CornerError {
  CameraCalibration camera;  // Its model and size; the values come from the parameters.
  Eigen::Vector3d board;
  Eigen::Vector2d image;
  bool operator()(double const* const* p, double* residual) const {
    CameraCalibration c = camera;
    c.fx = p[0][0], c.fy = p[0][1], c.cx = p[0][2], c.cy = p[0][3];
    const size_t n = c.distortion.size();
    for (size_t i = 0; i < n; ++i) c.distortion[i] = p[1][i];
    const double* pose = p[n > 0 ? 2 : 1];
    Eigen::Vector3d in_cam;
    ceres::AngleAxisRotatePoint(pose, board.data(), in_cam.data());
    in_cam += Eigen::Vector3d(pose[3], pose[4], pose[5]);
    if (in_cam.z() <= 1e-6) return false;
    const Eigen::Vector2d px = c.Project(in_cam);
    residual[0] = px.x() - image.x();
    residual[1] = px.y() - image.y();
    return std::isfinite(residual[0]) && std::isfinite(residual[1]);
  }
};

}  // namespace

RefinedCalibration RefineCalibration(const CameraCalibration& initial, const std::vector<SE3d>& cam_from_board,
                                     const std::vector<CornerView>& views) {
  std::vector<double> intrinsics = {initial.fx, initial.fy, initial.cx, initial.cy};
  std::vector<double> distortion = initial.distortion;
  std::vector<std::array<double, 6>> poses(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    const Eigen::Vector3d r = cam_from_board[v].So3().Log(), t = cam_from_board[v].Translation();
    poses[v] = {r.x(), r.y(), r.z(), t.x(), t.y(), t.z()};
  }
  ceres::Problem problem;
  const int n = static_cast<int>(distortion.size());
  int residuals = 0;
  for (size_t v = 0; v < views.size(); ++v)
    for (size_t i = 0; i < views[v].board.size(); ++i) {
      auto* cost = new ceres::DynamicNumericDiffCostFunction<CornerError, ceres::CENTRAL>(
          new CornerError{initial, views[v].board[i], views[v].image[i]});
      cost->AddParameterBlock(4);
      if (n > 0) cost->AddParameterBlock(n);
      cost->AddParameterBlock(6);
      cost->SetNumResiduals(2);
      std::vector<double*> blocks = {intrinsics.data()};
      if (n > 0) blocks.push_back(distortion.data());
      blocks.push_back(poses[v].data());
      problem.AddResidualBlock(cost, nullptr, blocks);
      residuals += 2;
    }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  RefinedCalibration out;
  out.camera = initial;
  out.camera.fx = intrinsics[0], out.camera.fy = intrinsics[1], out.camera.cx = intrinsics[2], out.camera.cy = intrinsics[3];
  out.camera.distortion = distortion;
  for (const auto& p : poses)
    out.cam_from_board.emplace_back(SO3d::Exp(Eigen::Vector3d(p[0], p[1], p[2])), Eigen::Vector3d(p[3], p[4], p[5]));

  // Deviations: the covariance of the camera's blocks, scaled by the residuals' variance.
  ceres::Covariance::Options cov_options;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> blocks = {{intrinsics.data(), intrinsics.data()}};
  if (n > 0) blocks.emplace_back(distortion.data(), distortion.data());
  const int dof = std::max(1, residuals - 4 - n - 6 * static_cast<int>(views.size()));
  const double variance = 2.0 * summary.final_cost / dof;
  if (covariance.Compute(blocks, &problem)) {
    std::vector<double> c4(16);
    covariance.GetCovarianceBlock(intrinsics.data(), intrinsics.data(), c4.data());
    for (int i = 0; i < 4; ++i) out.deviations.push_back(std::sqrt(c4[i * 4 + i] * variance));
    if (n > 0) {
      std::vector<double> cn(n * n);
      covariance.GetCovarianceBlock(distortion.data(), distortion.data(), cn.data());
      for (int i = 0; i < n; ++i) out.deviations.push_back(std::sqrt(cn[i * n + i] * variance));
    }
  }
  return out;
}

}  // namespace dsm
