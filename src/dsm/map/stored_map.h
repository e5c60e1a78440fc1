// SPDX-License-Identifier: MIT
// One map as a run leaves it, for a map file (mapfile/map_file.h): its keyframes and points, and
// the local window it ended with.
#pragma once

#include <vector>

#include "dsm/map/map.h"

namespace dsm {

struct StoredMap {
  Map map;
  std::vector<int> window;     // Temporal keyframes, oldest first.
  std::vector<int> covisible;  // Covisible keyframes of the window (DSM mode).
  // Per keyframe, the covisible keyframes of the window it was mapped in (fewer lists than
  // keyframes: the rest are empty).
  std::vector<std::vector<int>> covisibility;
};

}  // namespace dsm
