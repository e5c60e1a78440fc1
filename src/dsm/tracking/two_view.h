// SPDX-License-Identifier: MIT
// Two-view refinement of a relative motion from point correspondences.
//
// A RANSAC essential matrix is the best *minimal sample*: five tracks decide the motion and the
// others only vote. With the small baselines of a monocular start (a few centimetres, 1.5 deg of
// parallax) that leaves the direction of translation several degrees off, since a sideways
// translation and a rotation about the perpendicular axis move the image almost alike (the
// bas-relief ambiguity); the error is baked into the first map's depths. This refinement uses
// every inlier: it minimises the reprojection error in the second view over the rotation, the
// direction of translation and one inverse depth per track,
//
//   E(R, t, d) = sum_i rho( |pi(R x_i + d_i t) - m_i|^2 ),   |t| = 1,
//
// where x_i = (u_i, v_i, 1) is the track's ray in the reference (normalised coordinates), d_i its
// inverse depth there (the point is x_i / d_i, and d_i (R x_i / d_i + t) has the same projection),
// m_i the track in the second view, pi the pinhole projection in pixels and rho Cauchy's loss
//   rho(s) = c^2 / 2 * log(1 + s / c^2)     (IRLS weight 1 / (1 + s / c^2)),
// which, unlike Huber's, lets a wrong track's pull fade to nothing.
//
// Levenberg-Marquardt on 5 motion parameters (left rotation increment, two steps in the tangent
// plane of the unit translation) and n inverse depths; the depths are eliminated per track by the
// Schur complement, so each iteration solves a 5x5 system.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace dsm {

struct TwoViewProblem {
  std::vector<Eigen::Vector2d> reference;  // Normalised coordinates (x - cx) / fx, (y - cy) / fy.
  std::vector<Eigen::Vector2d> current;
  double fx = 1.0;
  double fy = 1.0;
  double loss_scale_px = 1.0;  // Cauchy's c.
};

struct TwoViewResult {
  Eigen::Matrix3d rotation;     // current_from_reference
  Eigen::Vector3d translation;  // unit length
  std::vector<double> idepth;   // per track, in the reference, for |t| = 1
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
};

// Refines (rotation, unit translation) from the given start; the inverse depths start at the
// least-squares values along each ray.
TwoViewResult RefineTwoView(const TwoViewProblem& problem, const Eigen::Matrix3d& rotation,
                            const Eigen::Vector3d& translation);

}  // namespace dsm
