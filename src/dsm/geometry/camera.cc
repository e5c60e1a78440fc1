// SPDX-License-Identifier: MIT
#include "dsm/geometry/camera.h"

#include <cmath>
#include <Eigen/LU>

#include "dsm/util/check.h"

namespace dsm {

CameraModel ParseCameraModel(const std::string& name, const std::string& where) {
  std::string n;
  for (char c : name) n.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  if (n == "pinhole" || n == "none") return CameraModel::kPinhole;
  if (n == "radtan" || n == "radial-tangential" || n == "plumb_bob" || n == "radial_tangential")
    return CameraModel::kRadTan;
  if (n == "equidistant" || n == "fisheye" || n == "kannala-brandt" || n == "kannalabrandt")
    return CameraModel::kEquidistant;
  if (n == "fov") return CameraModel::kFov;
  throw InputError(where + ": unknown camera model '" + name +
                   "' (expected pinhole, radtan, equidistant or fov)");
}

std::string CameraModelName(CameraModel model) {
  switch (model) {
    case CameraModel::kPinhole: return "pinhole";
    case CameraModel::kRadTan: return "radtan";
    case CameraModel::kEquidistant: return "equidistant";
    case CameraModel::kFov: return "fov";
  }
  return "unknown";
}

void CameraCalibration::Validate(const std::string& source) const {
  const auto fail = [&](const std::string& what) { throw InputError(source + ": " + what); };
  if (width < 16 || height < 16 || width > 16384 || height > 16384)
    fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not plausible");
  for (double v : {fx, fy, cx, cy})
    if (!std::isfinite(v)) fail("intrinsics must be finite numbers");
  if (!(fx > 0) || !(fy > 0)) fail("focal lengths must be positive");
  for (double d : distortion)
    if (!std::isfinite(d)) fail("distortion coefficients must be finite numbers");
  const size_t n = distortion.size();
  switch (model) {
    case CameraModel::kPinhole:
      for (double d : distortion)
        if (d != 0.0) fail("a pinhole camera takes no distortion coefficients");
      break;
    case CameraModel::kRadTan:
      if (n != 4 && n != 5) fail("radtan needs 4 or 5 distortion coefficients (k1 k2 p1 p2 [k3]), got " + std::to_string(n));
      break;
    case CameraModel::kEquidistant:
      if (n != 4) fail("equidistant needs 4 distortion coefficients (k1 k2 k3 k4), got " + std::to_string(n));
      break;
    case CameraModel::kFov:
      if (n != 1) fail("fov needs 1 distortion coefficient (omega), got " + std::to_string(n));
      if (!(distortion[0] > 0.0 && distortion[0] < M_PI)) fail("fov omega must be in (0, pi)");
      break;
  }
}

Eigen::Vector2d CameraCalibration::Distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double r = std::sqrt(r2);
  // Radial models: D = g(r) (x, y);  dD/dxy = g I + g'(r) / r (x, y)(x, y)^T.
  double g = 1.0, dg_over_r = 0.0;
  switch (model) {
    case CameraModel::kPinhole:
      if (J) J->setIdentity();
      return xy;
    case CameraModel::kRadTan: {
      const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3];
      const double k3 = distortion.size() > 4 ? distortion[4] : 0.0;
      const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
      const double dradial_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
      const Eigen::Vector2d out(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                                y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
      if (J) {
        (*J)(0, 0) = radial + 2.0 * x * x * dradial_dr2 + 2.0 * p1 * y + 6.0 * p2 * x;
        (*J)(0, 1) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 0) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 1) = radial + 2.0 * y * y * dradial_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
      }
      return out;
    }
    case CameraModel::kEquidistant: {
      const double k1 = distortion[0], k2 = distortion[1], k3 = distortion[2], k4 = distortion[3];
      if (r < 1e-8) {
        g = 1.0;
        dg_over_r = 2.0 * (k1 - 1.0 / 3.0);  // g ~= 1 + (k1 - 1/3) r^2 near the axis
      } else {
        const double th = std::atan(r);
        const double t2 = th * th;
        const double poly = 1.0 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4)));
        const double dpoly = 1.0 + t2 * (3.0 * k1 + t2 * (5.0 * k2 + t2 * (7.0 * k3 + t2 * 9.0 * k4)));
        const double th_d = th * poly;
        g = th_d / r;
        const double dth_d_dr = dpoly / (1.0 + r2);
        dg_over_r = (dth_d_dr * r - th_d) / (r2 * r);
      }
      break;
    }
    case CameraModel::kFov: {
      const double w = distortion[0];
      const double a = 2.0 * std::tan(w / 2.0);
      if (r < 1e-8) {
        g = a / w;
        dg_over_r = -2.0 * a * a * a / (3.0 * w);  // atan(a r) / (w r) ~= a/w (1 - a^2 r^2 / 3)
      } else {
        const double h = std::atan(a * r) / w;
        const double dh = a / (w * (1.0 + a * a * r2));
        g = h / r;
        dg_over_r = (dh * r - h) / (r2 * r);
      }
      break;
    }
  }
  if (J) *J = g * Eigen::Matrix2d::Identity() + dg_over_r * xy * xy.transpose();
  return g * xy;
}

Eigen::Vector2d CameraCalibration::Project(const Eigen::Vector3d& p, Eigen::Matrix<double, 2, 3>* J) const {
  const double iz = 1.0 / p.z();
  const Eigen::Vector2d xy(p.x() * iz, p.y() * iz);
  Eigen::Matrix2d J_dist;
  const Eigen::Vector2d d = Distort(xy, J ? &J_dist : nullptr);
  if (J) {
    Eigen::Matrix<double, 2, 3> J_xy_p;
    J_xy_p << iz, 0, -p.x() * iz * iz, 0, iz, -p.y() * iz * iz;
    *J = Eigen::DiagonalMatrix<double, 2>(fx, fy) * J_dist * J_xy_p;
  }
  return {fx * d.x() + cx, fy * d.y() + cy};
}

bool CameraCalibration::Unproject(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const {
  const Eigen::Vector2d target((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  Eigen::Vector2d xy = target;
  if (model == CameraModel::kPinhole) {
    *normalized = xy;
    return true;
  }
  // Gauss-Newton on D(xy) = target, from the distorted coordinates.
  for (int it = 0; it < 50; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d err = Distort(xy, &J) - target;
    if (err.squaredNorm() < 1e-24) break;
    if (std::abs(J.determinant()) < 1e-12) return false;
    xy -= J.lu().solve(err);
    if (!xy.allFinite() || xy.norm() > 1e3) return false;
  }
  *normalized = xy;
  return (Distort(xy) - target).norm() < 1e-9;
}

}  // namespace dsm
