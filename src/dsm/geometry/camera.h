// SPDX-License-Identifier: MIT
// Camera models. A 3-D point p_in_cam = (X, Y, Z), Z > 0, projects as
//   (x, y) = (X / Z, Y / Z)                 normalized coordinates
//   (xd, yd) = D(x, y)                      distortion of the model
//   (u, v) = (fx xd + cx, fy yd + cy)       pixel
// Pixel (0, 0) is the centre of the top-left pixel.
//
// Distortions D, with r = |(x, y)|:
//   pinhole      D = identity
//   radtan       radial (1 + k1 r^2 + k2 r^4 + k3 r^6) plus tangential (p1, p2)   [k1 k2 p1 p2 (k3)]
//   equidistant  theta = atan r, theta_d = theta (1 + k1 th^2 + k2 th^4 + k3 th^6 + k4 th^8),
//                D = theta_d / r * (x, y)                                          [k1 k2 k3 k4]
//   fov          D = atan(2 r tan(w / 2)) / (w r) * (x, y)                         [w]
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dsm {

enum class CameraModel { kPinhole, kRadTan, kEquidistant, kFov };

// Parses "pinhole", "radtan" (also "radial-tangential", "plumb_bob"), "equidistant" (also
// "fisheye", "kannala-brandt"), "fov"; throws InputError naming `where` otherwise.
CameraModel ParseCameraModel(const std::string& name, const std::string& where);
std::string CameraModelName(CameraModel model);

struct CameraCalibration {
  CameraModel model = CameraModel::kPinhole;
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  // See the table above.

  // Throws InputError naming `source` when sizes, focal lengths or distortion counts are invalid.
  void Validate(const std::string& source) const;

  // Pixel of a point in front of the camera; optional Jacobian d(u,v)/d(X,Y,Z).
  Eigen::Vector2d Project(const Eigen::Vector3d& p_in_cam, Eigen::Matrix<double, 2, 3>* J = nullptr) const;

  // Normalized coordinates (x, y) of pixel (u, v), inverting D by Gauss-Newton. Returns false if
  // the inversion does not converge (outside the model's valid field of view).
  bool Unproject(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const;

  // D and its 2x2 Jacobian on normalized coordinates.
  Eigen::Vector2d Distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J = nullptr) const;

  bool IsPinhole() const { return model == CameraModel::kPinhole; }
};

// The ideal pinhole camera every algorithm works with after undistortion.
struct PinholeCamera {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;

  Eigen::Vector2d Project(const Eigen::Vector3d& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
  // Ray with z = 1 through pixel (u, v).
  Eigen::Vector3d Unproject(double u, double v) const { return {(u - cx) / fx, (v - cy) / fy, 1.0}; }
  // The camera of pyramid level l: f / 2^l and (c + 0.5) / 2^l - 0.5 (pixel centres at integers).
  PinholeCamera AtLevel(int level) const {
    const double s = 1.0 / (1 << level);
    return {width >> level, height >> level, fx * s, fy * s, (cx + 0.5) * s - 0.5, (cy + 0.5) * s - 0.5};
  }
  Eigen::Matrix3d K() const {
    Eigen::Matrix3d k;
    k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
    return k;
  }
};

}  // namespace dsm
