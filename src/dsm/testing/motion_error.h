// SPDX-License-Identifier: MIT
// Errors of estimated motions against the truth, in degrees, for test assertions.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "dsm/lie/so3.h"

namespace dsm::testing {

// Angle of the rotation a b^-1.
inline double RotationErrorDeg(const SO3d& a, const SO3d& b) { return (a * b.Inverse()).Log().norm() * 180.0 / M_PI; }

// Angle between the directions of a and b (e.g. two translations of unknown scale).
inline double DirectionErrorDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace dsm::testing
