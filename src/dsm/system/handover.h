// SPDX-License-Identifier: MIT
// What the two sides of a System hand each other (system.h): a tracked frame for the mapping side
// (MappingJob), and the keyframe the tracking side aligns frames with (TrackingReference, with
// the map as a viewer shows it when asked). Each is immutable once handed over.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/mapping/map_points.h"
#include "dsm/photometric/residual.h"
#include "dsm/photometric/robust.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/rolling_shutter.h"

namespace dsm {

// The map as a viewer shows it, taken by the mapping side with a tracking reference when
// SystemSetup::map_snapshots is set; never changed after.
struct MapSnapshot {
  std::vector<LivePoint> points;
  std::vector<SE3d> world_from_cam;  // Every keyframe's, in id order ...
  std::vector<int> keyframe_frames;  // ... and its input frame index.
  // (keyframe, a covisible keyframe of the window it was mapped in).
  std::vector<std::pair<int, int>> covisibility;
};

// A tracked frame handed to the mapping side; its pose and brightness are relative to the
// reference keyframe it was tracked against (I_frame = e^alpha I_reference + beta).
struct MappingJob {
  int index = -1;
  int64_t t_ns = 0;
  double exposure = 1.0;
  std::shared_ptr<const ImagePyramid> pyramid;
  int reference = -1;
  SE3d frame_from_reference;
  double alpha = 0.0, beta = 0.0;
  int keyframe = -1;  // Its keyframe id when it becomes one.
  ErrorModel model;   // Fitted to its tracking residuals.
  double rmse = 0.0, inlier_ratio = 0.0;
  int relocalisations = 0;  // Confirmed on the tracking side before this frame.
  ReadoutTurn readout;      // A rolling shutter's turn through its readout (none: global).
};

// What tracking needs of its reference keyframe: published by the mapping side once the
// keyframe is mapped, never changed after.
struct TrackingReference {
  int keyframe = -1;
  std::shared_ptr<const ImagePyramid> pyramid;
  std::vector<ReferencePoint> points;
  // Of keyframes 0..keyframe, as the map had them then.
  std::vector<SE3d> cam_from_world;
  std::vector<AffineBrightness> affine;
  std::vector<double> exposure;
  int map_points = 0;  // Live points of the map then.
  double texture = 0.0;  // The keyframe's (FrameSignature::texture).
  double scale = 1.0;    // The keyframe's scale then (System::KeyframeScale).
  std::shared_ptr<const MapSnapshot> snapshot;  // With SystemSetup::map_snapshots.
};

}  // namespace dsm
