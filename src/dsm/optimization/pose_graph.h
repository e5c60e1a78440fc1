// SPDX-License-Identifier: MIT
// Pose-graph optimisation on Sim(3) (Strasdat, Montiel, Davison, "Scale Drift-Aware Large Scale
// Monocular SLAM", RSS 2010): the correction that closes a loop is spread over the keyframes of
// the loop, scale drift included, before the bundle adjustment refines the map.
//
// Node i is a keyframe's cam_from_world S_i = (s_i, R_i, t_i); an edge (i, j) measures
// S_ij = i_from_j. Its residual is the error E = S_ij S_j S_i^-1 (identity when the nodes agree
// with the measurement) written as (t_E, 2 vec(q_E), log s_E), times the edge's weight. The
// edges between keyframes of the map are measured at the poses before the loop (scale 1: they
// hold the map's shape); the loop edge carries the correction. Solved with Ceres
// (Levenberg-Marquardt, sparse normal Cholesky), the fixed nodes held.
#pragma once

#include <vector>

#include "dsm/lie/sim3.h"

namespace dsm {

struct PoseGraphEdge {
  int i = -1, j = -1;
  Sim3d i_from_j;
  double weight = 1.0;
};

struct PoseGraphResult {
  std::vector<Sim3d> cam_from_world;  // Per node.
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;
  double time_ms = 0.0;
};

// `cam_from_world`: the nodes' starting values; `fixed`: node indices held.
PoseGraphResult OptimizePoseGraph(const std::vector<Sim3d>& cam_from_world, const std::vector<PoseGraphEdge>& edges,
                                  const std::vector<int>& fixed, int max_iterations = 20);

// The same for the keyframes' affine brightness, which drifts along a loop as the poses do (each
// keyframe's is estimated relative to the ones before). Node i is (a_i, b_i); an edge (i, j)
// measures the brightness of j relative to i, I_j = e^alpha I_i + beta, with the residual
//   ( (a_j - a_i - alpha) / sigma_a,  (b_j - e^alpha b_i - beta) / sigma_b ).
// (Exposure times are the caller's: alpha here is the part of the change that a and b explain.)
struct BrightnessEdge {
  int i = -1, j = -1;
  double alpha = 0.0, beta = 0.0;
};
std::vector<Eigen::Vector2d> OptimizeBrightnessGraph(const std::vector<Eigen::Vector2d>& ab,
                                                     const std::vector<BrightnessEdge>& edges,
                                                     const std::vector<int>& fixed, double sigma_a = 0.01,
                                                     double sigma_b = 1.0);

}  // namespace dsm
