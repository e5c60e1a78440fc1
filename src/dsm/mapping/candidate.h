// SPDX-License-Identifier: MIT
// Candidate points (paper VI-C): pixels of a keyframe whose inverse depth is not known yet, refined
// by searching along the epipolar line in every new tracked frame until they are precise enough
// to be activated into the map.
//
// For a candidate at host pixel u and a frame with (R, t) = frame_from_host, the point with
// inverse depth rho projects to
//   U(rho) = pi( K R K^-1 (u, 1) + rho K t )
// which traces the epipolar segment between U(rho_min) and U(rho_max). The search steps along it
// one pixel at a time comparing the 8-pixel pattern (with the brightness transfer), keeps the best
// and second-best errors (quality = second / best, ignoring +-2 steps around the best), refines
// the best by Gauss–Newton along the line, and maps the match +- its pixel uncertainty back to an
// inverse-depth interval. The pixel uncertainty grows as the image gradient turns perpendicular to
// the line: err_px = 0.2 + 0.2 (a + b) / a, a = sum (g . l)^2, b = sum (g . l_perp)^2.
#pragma once

#include <array>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/photometric/residual.h"

namespace dsm {

enum class TraceStatus {
  kUninitialized,  // Never traced.
  kGood,           // Matched; interval updated.
  kSkipped,        // Search range too short to tell (no parallax yet): nothing learned.
  kBadCondition,   // Gradient parallel to... perpendicular to the line: no information.
  kOutOfBounds,    // Projects outside the frame.
  kOutlier,        // No acceptable match.
};

struct EpipolarOptions {
  static constexpr double max_search_fraction = 0.0375;  // Of the image diagonal, when rho_max is unknown.
  static constexpr double min_search_px = 1.5;
  static constexpr double max_pixel_error = 10.0;        // Beyond this uncertainty a trace is a bad condition.
  static constexpr float max_energy = 12.f * 12.f * kPatternSize;  // Of the best match, else an outlier.
  static constexpr int gauss_newton_iterations = 3;
};

struct Candidate {
  Eigen::Vector2f pixel = Eigen::Vector2f::Zero();  // Level 0, host.
  std::array<float, kPatternSize> value{};          // Host intensities of the pattern.
  std::array<Eigen::Vector2f, kPatternSize> gradient{};
  float idepth_min = 0.f;
  float idepth_max = -1.f;  // < 0: unknown (unbounded).
  float quality = 0.f;
  float pixel_interval = 1e9f;  // Length of the last matched interval, pixels.
  TraceStatus status = TraceStatus::kUninitialized;
  int outlier_count = 0;
  bool removed = false;

  float Idepth() const { return idepth_max < 0 ? idepth_min : 0.5f * (idepth_min + idepth_max); }
};

// Samples the host pattern; false near the border.
bool MakeCandidate(const ImagePyramid& host, const Eigen::Vector2f& pixel, Candidate* candidate);

// Brightness transfer host -> frame: I_h - b_h = s (I_f - b_f).
struct Transfer {
  float s = 1.f, b_host = 0.f, b_frame = 0.f;
};

TraceStatus TraceCandidate(Candidate* candidate, const ImagePyramid& frame, const PinholeCamera& camera,
                           const SE3d& frame_from_host, const Transfer& transfer, const EpipolarOptions& options);

}  // namespace dsm
