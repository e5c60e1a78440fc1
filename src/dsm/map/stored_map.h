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
  // The image noise the map's frames had (image/noise.h, grey levels): it chose how residuals
  // sample images and which candidates are kept (MappingSide::ChooseNoiseHandling), and a map taken up
  // again keeps that choice.
  double image_noise_sigma = 0.0;
  // The tracking-quality levels at the map's end (tracking/tracking_quality.h: median residual
  // and texture of the last trusted frames; 0: none), which judge the first frames tracked in it
  // again.
  double residual_level = 0.0, texture_level = 0.0;
};

}  // namespace dsm
