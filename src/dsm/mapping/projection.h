// SPDX-License-Identifier: MIT
// Moving map points between keyframes. A point is stored by its host pixel u and inverse depth
// rho; in the host camera it is X_h = K^-1 u / rho, in the world X_w = T_hw^-1 X_h, and in a
// target keyframe X_t = T_tw X_w.
#pragma once

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"

namespace dsm {

Eigen::Vector3d PointInWorld(const Map& map, const PinholeCamera& camera, const Point& point);

// Pixel and inverse depth of `point` in keyframe `target`; false when behind the camera or within
// `border` pixels of the image edge.
bool ProjectPoint(const Map& map, const PinholeCamera& camera, const Point& point, int target, float border,
                  Eigen::Vector2f* pixel, float* idepth);

// Angle (degrees) at the point between the rays to the host centre and to `target`'s centre: a
// large change of viewpoint makes occlusion and a different appearance likely.
double ViewAngleDeg(const Map& map, const PinholeCamera& camera, const Point& point, int target);

}  // namespace dsm
