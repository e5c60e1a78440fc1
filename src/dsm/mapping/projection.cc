// SPDX-License-Identifier: MIT
#include "dsm/mapping/projection.h"

#include <algorithm>
#include <cmath>

namespace dsm {

Eigen::Vector3d PointInWorld(const Map& map, const PinholeCamera& camera, const Point& point) {
  const Eigen::Vector3d p_host = camera.Unproject(point.pixel.x(), point.pixel.y()) / point.idepth;
  return map.keyframe(point.host).cam_from_world.Inverse() * p_host;
}

bool ProjectPoint(const Map& map, const PinholeCamera& camera, const Point& point, int target, float border,
                  Eigen::Vector2f* pixel, float* idepth) {
  const Eigen::Vector3d p_target = map.keyframe(target).cam_from_world * PointInWorld(map, camera, point);
  if (p_target.z() <= 1e-6) return false;
  const Eigen::Vector2d u = camera.Project(p_target);
  if (u.x() < border || u.y() < border || u.x() > camera.width - 1 - border || u.y() > camera.height - 1 - border)
    return false;
  *pixel = u.cast<float>();
  *idepth = static_cast<float>(1.0 / p_target.z());
  return true;
}

double ViewAngleDeg(const Map& map, const PinholeCamera& camera, const Point& point, int target) {
  const Eigen::Vector3d x = PointInWorld(map, camera, point);
  const Eigen::Vector3d a = map.keyframe(point.host).Centre() - x, b = map.keyframe(target).Centre() - x;
  const double c = a.dot(b) / std::max(1e-12, a.norm() * b.norm());
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace dsm
