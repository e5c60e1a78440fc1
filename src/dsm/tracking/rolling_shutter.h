// SPDX-License-Identifier: MIT
// Rolling shutter: the sensor exposes row v at t0 + v * delta, where t0 is the frame's timestamp
// (its first row's) and delta the line delay; a camera that turns during the readout sees each
// row from another orientation, bending straight lines and shifting the lower rows by pixels
// (90 deg/s over a 15 ms readout: about 9 px at f = 384).
//
// The camera turning at angular velocity w (rad/s, in the camera frame: cam_tau_from_cam_t0 has
// the rotation R(tau) = Exp(w tau)) sees at row time tau the direction it saw at t0 along x as
// R(tau) x. RectifyRotation resamples an image as a global shutter at t0 would have taken it:
// output pixel p takes the input's value at
//   q = pi(K R(tau) K^-1 p),   tau = q_v delta,
// solved per output row by fixed-point iteration on tau at the row's centre (q_v moves by a few
// pixels, so tau by a few line delays: the iteration converges in two steps, and the row's other
// pixels differ from the centre's tau by well under a pixel's worth of turn). Bilinear sampling;
// source pixels beyond the border take the nearest border pixel.
//
// Translation during the readout is not corrected: it moves a point by (v tau) / z, under a pixel
// at hand-held speeds (0.3 m/s, 15 ms, points 2 m away), while turning moves every point alike,
// whatever its depth, which is why an image warp can undo it.
#pragma once

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"

namespace dsm {

// The camera's turn through a rolling shutter's readout: level-0 row v of a frame is seen from the
// camera turned by Exp(w v delta) from its pose at the timestamp. Zero delay: a global shutter.
struct ReadoutTurn {
  double line_delay_s = 0.0;
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // w, rad/s, camera frame.
};

Image<float> RectifyRotation(const Image<float>& image, const PinholeCamera& camera, const ReadoutTurn& turn);

}  // namespace dsm
