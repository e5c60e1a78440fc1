// SPDX-License-Identifier: MIT
// Helpers shared by the two sides' source files (tracking_*.cc, mapping_*.cc).
#pragma once

#include <chrono>
#include <cmath>

#include <memory>

#include "dsm/geometry/camera.h"
#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/photometric/residual.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/rolling_shutter.h"

namespace dsm::internal {

// `tracker` over `levels` pyramid levels, the coarser ones added with the iterations of its
// coarsest: for an alignment from far away (relocalisation, a loop's verification).
inline TrackerOptions OverLevels(TrackerOptions tracker, int levels) {
  while (tracker.levels < levels) {
    tracker.iterations.insert(tracker.iterations.begin() + tracker.levels, tracker.iterations[tracker.levels - 1]);
    ++tracker.levels;
  }
  return tracker;
}

inline double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A frame's pyramid (`levels` levels) as a global shutter at its timestamp would have seen it, the
// camera turning by `turn` through the readout (tracking/rolling_shutter.h); without gradients.
inline std::shared_ptr<const ImagePyramid> GlobalShutterPyramid(const ImagePyramid& pyramid, const PinholeCamera& camera,
                                                                const ReadoutTurn& turn, int levels) {
  return std::make_shared<const ImagePyramid>(RectifyRotation(pyramid.ValuesLevel0(), camera, turn), levels,
                                              /*gradients=*/false);
}

// T^s on the geodesic from the identity.
inline SE3d Scale(const SE3d& T, double s) { return SE3d::Exp(s * T.Log()); }

// The same, but T itself, bit for bit, for s = 1 (the motion model over one frame step).
inline SE3d ScaleSteps(const SE3d& T, double s) { return s == 1.0 ? T : Scale(T, s); }

// A rotation by `angle` radians about camera axis `axis` (0: x, 1: y, 2: z), to turn a pose guess.
inline SE3d RotationAbout(int axis, double angle) {
  Eigen::Matrix<double, 6, 1> xi = Eigen::Matrix<double, 6, 1>::Zero();
  xi(3 + axis) = angle;
  return SE3d::Exp(xi);
}

// Whether cameras a and b (cam_from_world) see from two places: their centres more than a tenth of
// the scene's depth apart (1 / mean_idepth) or their views turned by more than 5 degrees apart.
inline bool OtherPlace(const SE3d& a, const SE3d& b, double mean_idepth) {
  const SE3d b_from_a = b * a.Inverse();
  return b_from_a.Inverse().Translation().norm() * mean_idepth > 0.1 || b_from_a.So3().Log().norm() > 5.0 * M_PI / 180.0;
}

// The absolute brightness of a frame tracked against `ref` with I_f = e^alpha I_ref + beta: from
//   I_ref - b_ref = e^(a_ref - a_f) tau_ref / tau_f (I_f - b_f)
// follow a_f = a_ref + alpha - log(tau_f / tau_ref) and b_f = beta + e^alpha b_ref.
inline AffineBrightness FrameBrightness(const AffineBrightness& ref, double ref_exposure, double alpha, double beta,
                                        double exposure) {
  return {ref.a + alpha - std::log(exposure / ref_exposure), beta + std::exp(alpha) * ref.b};
}

// FrameBrightness inverted: the (alpha, beta) of a frame of absolute brightness `frame` relative
// to `ref`: alpha = a_f - a_ref + log(tau_f / tau_ref), beta = b_f - e^alpha b_ref.
inline void RelativeBrightness(const AffineBrightness& frame, double exposure, const AffineBrightness& ref,
                               double ref_exposure, double* alpha, double* beta) {
  *alpha = frame.a - ref.a + std::log(exposure / ref_exposure);
  *beta = frame.b - std::exp(*alpha) * ref.b;
}

}  // namespace dsm::internal
