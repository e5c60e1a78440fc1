// SPDX-License-Identifier: MIT
// The synthetic sequences: a scene, a camera, a trajectory and photometric parameters per frame,
// all deterministic functions of the options (the seed varies textures and hand-held jitter).
//
//   loop      a furnished room walked around twice along the same loop (re-visits)
//   shake     back-and-forth hand-held motion in front of a wall (like the EuRoC start)
//   forward   along a corridor, then back the same way (reversing, same heading)
//   rotation  strong rotations with little translation
//   exposure  like loop, with exposure time, gain and offset changing over time
//   orbit     around a room's middle looking at it: a pillar and a table pass close to the camera
//             in front of weakly textured walls (strong parallax, occlusions), two laps
//   pan       hand-held panning from the first frame, the first 5 s mostly at one wall with
//             almost no translation (a hard start), then a slow walk back
//   block     a 98 m lap of a ring corridor around a building block, and a fifth of a lap more:
//             the drift of a long loop is far beyond what re-observation alone can close
//   twins     down a corridor whose second half is an exact copy of its first (perceptual
//             aliasing: a place that looks seen before but is not)
//   handheld  a phone held out in the furnished room and turned about in yaw, pitch and roll
//             (peaks near 90 deg/s) while the body sways a little: mostly rotation
//   uturn     down the corridor facing the way it goes, a U-turn at the far end, and back along
//             the other side facing back: the walls seen again from the other way
//   swing     two laps walked around the furnished room facing the way it goes, while the
//             exposure time swings +-40% and the gain +-10% (the gain not in the recording)
//
// Each scene can be seen through any camera model's lens (SynthOptions::model): the same focal
// length and principal point, and the model's TypicalDistortion.
//
// With a rolling shutter (line_delay_us > 0) each image row is seen at its own time: row v of
// frame i at t_i + v * line_delay, the frame's timestamp t_i being its first row's, and its
// ground truth pose the camera's then.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/lie/se3.h"
#include "dsm/synth/lens_rays.h"
#include "dsm/synth/scene.h"

namespace dsm::synth {

struct SynthOptions {
  std::string scene = "loop";
  int frames = 0;         // 0: the scene's default length.
  uint32_t seed = 1;
  int width = 640;        // Image size; focal length 0.6 * width (about 80 degrees across).
  int height = 480;
  double rate_hz = 20.0;
  double noise_sigma = 1.0;  // Gaussian image noise, grey levels.
  double vignette = 0.0;     // Brightness loss in the corners (0..0.8); written as vignette.png.
  double blur_sigma = 0.0;   // Gaussian optical blur, pixels.
  bool depth = false;        // Also write per-frame depth maps.
  std::string defects;       // Bad frames to inject (defects.h), e.g. "black:20-24,corrupt:30".
  bool turned_textures = false;  // Textures that do not repeat along the surfaces (Texture::turned).
  bool plain_pillars = false;    // Floor-to-ceiling cylinders without texture (Scene::PlainPillars).
  double line_delay_us = 0.0;    // Rolling shutter: the time between two rows' exposures (0: global).
  // The lens: a pinhole, or the pinhole's focal length and principal point with the model's
  // TypicalDistortion (the images are rendered through it, camera.yaml gives it).
  CameraModel model = CameraModel::kPinhole;

  void Validate() const;  // Throws InputError naming the option.
};

std::vector<std::string> SceneNames();
// The scene names joined by `separator`, the last two by `last` ("loop, shake, ... or pan").
std::string SceneNameList(const std::string& separator, const std::string& last);
int DefaultFrames(const std::string& scene);

// Per-frame photometric parameters: I = gain * (exposure_ms / 10) * 255 * albedo * V + offset.
struct Photometry {
  double exposure_ms = 10.0;
  float gain = 1.f;
  float offset = 0.f;
};

struct SynthSequence {
  Scene scene;
  PinholeCamera camera;                  // The focal length and principal point.
  std::shared_ptr<const LensRays> lens;  // Null for a pinhole; else the lens, on top of `camera`.
  std::vector<int64_t> t_ns;
  std::vector<SE3d> world_from_cam;  // At t_ns (pose_at(i)).
  std::vector<Photometry> photometry;
  // world_from_cam at frame position f: frame i at f = i, the time between frames linear in f.
  std::function<SE3d(double f)> pose_at;
  double line_delay_frames = 0.0;  // Rolling shutter: the delay between rows in frame intervals.
  size_t size() const { return world_from_cam.size(); }
  // Frame i's camera at each row's exposure (row v at i + v * line_delay_frames).
  std::vector<SE3d> RowPoses(size_t i) const;
  // The camera as camera.yaml gives it: the lens's, or the pinhole's.
  CameraCalibration Calibration() const;
};

SynthSequence MakeSequence(const SynthOptions& options);

// world_from_cam for a camera at `position` looking at `target` (camera x right, y down, z ahead;
// the image up direction follows world +z).
SE3d LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target);

}  // namespace dsm::synth
