// SPDX-License-Identifier: MIT
// The map's live points as a user sees them: world position, grey value, host and observations
// (for exports and viewers; the algorithms work on Point directly).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"

namespace dsm {

struct LivePoint {
  Eigen::Vector3f world;  // X_w = T_hw^-1 K^-1 u / rho (projection.h).
  uint8_t grey = 0;       // The host's level-0 intensity at the nearest pixel, clamped to 0..255.
  int host = -1;
  int observations = 0;   // Keyframes that see it as an inlier, the host not counted.
};

// Every point not removed, in id order.
std::vector<LivePoint> LivePoints(const Map& map, const PinholeCamera& camera);

}  // namespace dsm
