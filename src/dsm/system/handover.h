// SPDX-License-Identifier: MIT
// What the two sides of a System (system.h) hand each other, and the one way the tracking side
// (tracking_side.h) reaches the mapping side (mapping_side.h): MappingInbox.
//
//   tracking side --MapStart, MappingJob-->  mapping side   (jobs, run in the order handed over)
//   tracking side <--TrackingReference----   mapping side   (the newest keyframe, published)
//   tracking side <--IdleMap, FramePose---   mapping side   (only while it is idle)
//
// A MapStart, MappingJob and TrackingReference are immutable once handed over. The map itself is
// the mapping side's: the tracking side reads it only through an IdleMap, lent while nothing is
// handed to the mapping side (a lost camera's relocalisation).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/map/map.h"
#include "dsm/mapping/map_points.h"
#include "dsm/photometric/residual.h"
#include "dsm/photometric/robust.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/initializer.h"
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
  double scale = 1.0;    // The keyframe's scale then (MappingSide::KeyframeScale).
  std::shared_ptr<const MapSnapshot> snapshot;  // With SystemSetup::map_snapshots.
};

// A frame the initialiser kept until the map starts.
struct InitFrame {
  int index = -1;
  int64_t t_ns = 0;
  double exposure = 1.0;
  std::shared_ptr<const ImagePyramid> pyramid;
};

// The map's start, from the two-view initialisation: keyframes `first` and `last` (pyramids as a
// global shutter saw them) with the initialiser's points, hosted by `first`; the frames between
// them are tracked by the mapping side once the young map has settled.
struct MapStart {
  InitFrame first, last;
  SE3d kf1_from_kf0;
  std::vector<InitPoint> points;
  std::vector<InitFrame> between;  // In order.
  int steps = 1;                   // Frame steps from `first` to `last`.
};

// A tracked frame's pose, relative to the keyframe it was tracked against.
struct FramePose {
  int64_t t_ns = 0;
  int reference = -1;  // Keyframe id the pose is relative to (-1: not tracked).
  SE3d frame_from_reference;
  // > 0 for the frames between the two initial keyframes: the distance between the two when the
  // frame was tracked. The first bundle adjustments still rescale the young map about keyframe 0
  // (held fixed), by ~5% on a hand-held start, so the frame's offset from its keyframe (0 or 1)
  // is scaled by that distance's change.
  double init_baseline = 0.0;
  // The reference keyframe's scale (TrackingReference::scale) when the frame was tracked: a loop
  // closure that rescales the keyframe later scales the frame's offset from it alike.
  double reference_scale = 1.0;
  // frame_from_reference with the change of the initial keyframes' distance applied: `baseline`
  // is that distance now (MappingSide::InitBaseline).
  SE3d AtBaseline(double baseline) const {
    SE3d out = frame_from_reference;
    if (init_baseline > 0.0) out.SetTranslation(out.Translation() * (baseline / init_baseline));
    return out;
  }
};

// The mapping side's map, lent to the tracking side while the mapping side is idle
// (MappingInbox::WaitUntilIdle); valid until the next job is handed over.
class IdleMap {
 public:
  virtual const Map& map() const = 0;
  // Points observed in keyframe kf (hosted, or an inlier observation), for tracking against it.
  virtual std::vector<ReferencePoint> PointsSeenIn(int kf) = 0;
  // A tracking reference of keyframe kf with `points` (`pyramid`: kf's, when the map holds none).
  virtual std::shared_ptr<const TrackingReference> MakeReference(int kf, std::vector<ReferencePoint> points,
                                                                 std::shared_ptr<const ImagePyramid> pyramid) const = 0;
  // ORB features of keyframes, by id: the tracking side adds those it computes.
  virtual std::map<int, OrbFeatures>& keyframe_features() = 0;
  // `ref` becomes the published reference: the one the next keyframe is mapped relative to.
  virtual void Republish(std::shared_ptr<const TrackingReference> ref) = 0;

 protected:
  ~IdleMap() = default;
};

// The mapping side as the tracking side reaches it. Sequential, a job is done when the call
// returns; threaded, it runs on the mapping thread in the order handed over, and the waits below
// block the tracking side until the mapping side has done what they name.
class MappingInbox {
 public:
  // Builds the map from `start` now (the mapping side is idle before the map starts), publishes
  // keyframe 1 with the initialiser's depths, and maps keyframe 1 as a keyframe job.
  virtual void StartMap(MapStart start) = 0;
  // A tracked frame: its candidate tracing, and its mapping when it is a keyframe.
  virtual void Submit(MappingJob job) = 0;
  // The newest reference published (null before the map starts).
  virtual std::shared_ptr<const TrackingReference> Published() const = 0;
  virtual bool threaded() const = 0;
  // Keyframe jobs queued or running / not settled (their adjustments after publication) (0 sequential).
  virtual int KeyframesPending() const = 0;
  virtual int KeyframesUnsettled() const = 0;
  virtual void WaitForKeyframes() = 0;
  // Until every keyframe is settled, but no later than `until`; true when none is left.
  virtual bool WaitForSettledKeyframesUntil(std::chrono::steady_clock::time_point until) = 0;
  // Waits until every job handed over is done (`urgent`: long adjustments stop early) and lends the map.
  virtual IdleMap& WaitUntilIdle(bool urgent) = 0;

 protected:
  ~MappingInbox() = default;
};

}  // namespace dsm
