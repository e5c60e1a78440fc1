// SPDX-License-Identifier: MIT
// The map as files a point-cloud viewer opens (io/ply.h), written beside a map's trajectories:
//   map.ply        every live point: x y z (world), its host pixel's grey value as red = green =
//                  blue, `host` (keyframe id) and `observations` (keyframes that see it as an
//                  inlier, the host not counted)
//   keyframes.ply  every keyframe's camera centre: x y z, `keyframe` (id) and `frame` (input index)
#pragma once

#include "dsm/geometry/camera.h"
#include "dsm/io/ply.h"
#include "dsm/map/map.h"

namespace dsm {

PlyCloud MapPointCloud(const Map& map, const PinholeCamera& camera);
PlyCloud KeyframeCloud(const Map& map);

}  // namespace dsm
