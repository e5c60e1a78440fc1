// SPDX-License-Identifier: MIT
// The rays of a camera seen through its lens, for the renderer (renderer.h).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"

namespace dsm::synth {

// The distortion of a typical lens of `model` (camera.h's table), as the tests and `dsm synth`
// use it: radtan a barrel of -0.28 r^2, equidistant and fov mild departures from their own
// projections; none for a pinhole.
std::vector<double> TypicalDistortion(CameraModel model);

// The rays of a camera of any model (camera.h), precomputed: each pixel centre's unit ray in the
// camera frame (CameraCalibration::Unproject) with the angle the pixel spans, and the normalized
// coordinates (x / z, y / z) of every pixel corner, from which a block of pixels' bounding cone
// follows. Pixels the model cannot unproject see nothing.
class LensRays {
 public:
  struct Pixel {
    Eigen::Vector3f unit = Eigen::Vector3f::Zero();  // Zero: the pixel sees nothing.
    float angle = 0.f;                               // sqrt of the solid angle the pixel spans.
  };

  explicit LensRays(const CameraCalibration& camera);

  const CameraCalibration& camera() const { return camera_; }
  int width() const { return camera_.width; }
  int height() const { return camera_.height; }
  const Pixel& At(int u, int v) const { return pixels_[static_cast<size_t>(v) * camera_.width + u]; }
  // The normalized coordinates of corner (i, j), pixel position (i - 0.5, j - 0.5); NaN where the
  // model cannot unproject it.
  const Eigen::Vector2f& Corner(int i, int j) const { return corners_[static_cast<size_t>(j) * (camera_.width + 1) + i]; }

  // The cone (in the camera frame, corners in order around it) of every ray through pixels
  // [u0, u1) x [v0, v1) out to their outer edges: the bounding box of the block's border corners
  // in normalized coordinates (the lens maps the block's inside within its border), widened by
  // 1%. False when a border corner cannot be unprojected.
  bool Cone(int u0, int v0, int u1, int v1, std::array<Eigen::Vector3f, 4>* corners) const;

 private:
  CameraCalibration camera_;
  std::vector<Pixel> pixels_;
  std::vector<Eigen::Vector2f> corners_;
};

}  // namespace dsm::synth
