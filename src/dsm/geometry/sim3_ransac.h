// SPDX-License-Identifier: MIT
// A similarity between two views of one place from 3D-3D matches (monocular maps drift in scale,
// so two passes through a place agree up to a Sim(3)): RANSAC over minimal sets of three matches,
// each solved by Umeyama's alignment (umeyama.h), then refined on all inliers.
//
// Match i holds a point in the cameras of views a and b (x_a, x_b: camera coordinates at each
// view's own scale). For b_from_a = S, it is an inlier when both reprojections land within
// `max_px` of the other view's measurement:
//   | pi(S x_a) - pi(x_b) | < max_px  and  | pi(S^-1 x_b) - pi(x_a) | < max_px.
// Deterministic for a given seed.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/lie/sim3.h"

namespace dsm {

struct Sim3RansacOptions {
  int iterations = 300;
  double max_px = 4.0;
  int min_inliers = 20;
  uint32_t seed = 1;
};

struct Sim3RansacResult {
  bool ok = false;          // At least min_inliers inliers.
  Sim3d b_from_a;
  std::vector<int> inliers;  // Indices into the matches.
};

Sim3RansacResult EstimateSim3Ransac(const std::vector<Eigen::Vector3d>& in_a, const std::vector<Eigen::Vector3d>& in_b,
                                    const PinholeCamera& camera, const Sim3RansacOptions& options);

}  // namespace dsm
