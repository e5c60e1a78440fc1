// SPDX-License-Identifier: MIT
// The part of the map mapped since a relocalisation, moved onto the older map when the camera
// sees that map again (SystemOptions::rejoin_min_outliers).
//
// A relocalised pose is all that joins the part mapped after it to the older map. When the lost
// frame overlaps the keyframe it was aligned with by a small share (the camera moved on while it
// was lost), a shift along the image and a turn about the other image axis trade against each
// other, and the pose ends a few percent of the baseline off; the part mapped from it carries the
// offset whole, as nothing else ties it to the older map. When the camera comes back to the older
// map, the covisible keyframes are held and the window holds the part's own geometry, so the
// window's adjustment does not move the part onto the old points: it marks them outliers.
// Then the new keyframe is aligned with the old keyframe that hosts most of those outliers (the
// keyframe's image against that keyframe's points, from the pose it has), and every keyframe
// since the relocalisation moves by the correction, with its points (hosted by inverse depth):
//   M = C'^-1 C   (world of the older map from world of the part; C, C': the new keyframe's
//                  cam_from_world before and after),
//   C_k <- C_k M^-1   for every keyframe k of the part.
// The observations that the window judged at the poses it had are judged again, and the loop
// adjustment that follows (AdjustLoop) settles the rest, scale included.

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include "dsm/mapping/projection.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/util/median.h"

namespace dsm {

namespace {

// Largest correction taken for a rejoin: beyond it the alignment more likely found a place that
// looks alike than the same place a few percent off. Translation over the old keyframe's mean
// depth; rotation in degrees.
constexpr double kMaxStep = 0.1;
constexpr double kMaxTurnDeg = 5.0;
// Smallest correction taken: the median shift of the old points in the keyframe (pixels).
constexpr float kMinShiftPx = 8.f;

}  // namespace

bool MappingSide::RejoinAfterRelocalisation(int newest) {
  const int min_outliers = options_.rejoin_min_outliers;
  if (options_.mode != MapMode::kFull || rejoin_first_ < 0 || min_outliers == 0 || newest < rejoin_first_)
    return false;
  // The new keyframe's observations of the points that the older map's covisible keyframes host.
  int inliers = 0, outliers = 0;
  std::map<int, int> outliers_of;  // Per host keyframe.
  std::vector<int> observed;
  for (int h : covisible_) {
    if (h >= rejoin_first_) continue;
    for (int pid : map_.keyframe(h).points) {
      const Point& p = map_.point(pid);
      const Observation* o = p.removed ? nullptr : p.FindObservation(newest);
      if (o == nullptr) continue;
      observed.push_back(pid);
      if (o->outlier) {
        ++outliers;
        ++outliers_of[h];
      } else {
        ++inliers;
      }
    }
  }
  if (outliers < min_outliers || outliers < 3 * inliers) return false;
  const int old = std::max_element(outliers_of.begin(), outliers_of.end(), [](const auto& a, const auto& b) {
                    return a.second < b.second;
                  })->first;
  const Keyframe& o = map_.keyframe(old);
  const Keyframe& k = map_.keyframe(newest);
  const std::vector<ReferencePoint> points = PointsSeenIn(old);
  const std::shared_ptr<const ImagePyramid> pyramid = o.PyramidOrRebuilt();
  FrameTracker tracker(options_.tracker);
  tracker.SetReference(pyramid.get(), camera_, points);
  double alpha, beta;
  internal::RelativeBrightness(k.affine, k.exposure, o.affine, o.exposure, &alpha, &beta);
  const TrackResult r = tracker.Track(k.Pyramid(), k.cam_from_world * o.cam_from_world.Inverse(), alpha, beta);
  const SE3d corrected = r.frame_from_keyframe * o.cam_from_world;
  const SE3d to_old = corrected.Inverse() * k.cam_from_world;  // M
  const double step = (corrected.Inverse().Translation() - k.Centre()).norm() * tracker.MeanIdepth();
  const double turn_deg = to_old.So3().Log().norm() * 180.0 / M_PI;
  if (!r.ok || r.inlier_ratio < options_.quality.min_inlier_ratio || step > kMaxStep || turn_deg > kMaxTurnDeg)
    return false;
  const SE3d from_old = to_old.Inverse();
  const auto consistent = [&] {
    const std::vector<uint8_t> seen = SeenIn(observed, newest);
    return static_cast<int>(std::count(seen.begin(), seen.end(), 1));
  };
  const int before = consistent();
  // Where the old points land in the keyframe, before and after the correction.
  const auto landing = [&] {
    std::vector<Eigen::Vector2f> px(observed.size());
    float rho;
    for (size_t i = 0; i < observed.size(); ++i)
      if (!ProjectPoint(map_, camera_, map_.point(observed[i]), newest, -1e6f, &px[i], &rho)) px[i].setConstant(NAN);
    return px;
  };
  const std::vector<Eigen::Vector2f> from = landing();
  // The checks read the new keyframe's pose alone (the old points' hosts stay): it moves first.
  const SE3d pose = k.cam_from_world;
  map_.keyframe(newest).cam_from_world = pose * from_old;
  const int after = consistent();
  const std::vector<Eigen::Vector2f> to = landing();
  std::vector<float> moved;
  for (size_t i = 0; i < to.size(); ++i)
    if (std::isfinite(from[i].x()) && std::isfinite(to[i].x())) moved.push_back((to[i] - from[i]).norm());
  const float shift_px = moved.empty() ? 0.f : Median(moved);
  // The old points must agree with the moved part: most of them consistent in the keyframe
  // (observation_check.h), where few were. And the correction must move them beyond the
  // adjustments' reach: a shift of a few pixels the loops that follow close by themselves, bending
  // the part where a rigid move cannot.
  if (2 * after < static_cast<int>(observed.size()) || after < 2 * before || shift_px < kMinShiftPx) {
    map_.keyframe(newest).cam_from_world = pose;
    return false;
  }
  for (int j = rejoin_first_; j < map_.NumKeyframes(); ++j)
    if (j != newest) map_.keyframe(j).cam_from_world = map_.keyframe(j).cam_from_world * from_old;
  // The window's judgements at the poses it had: made again by the next adjustments.
  for (int h : covisible_) {
    if (h >= rejoin_first_) continue;
    for (int pid : map_.keyframe(h).points) {
      Point& p = map_.point(pid);
      if (p.removed) continue;
      for (Observation& ob : p.observations)
        if (ob.target >= rejoin_first_ && std::find(window_.begin(), window_.end(), ob.target) != window_.end())
          ob.outlier = false;
    }
  }
  MappingStats::KeyframeLog& log = stats_->per_keyframe.back();
  log.rejoined = true;
  log.rejoin_step = step;
  log.rejoin_deg = turn_deg;
  log.rejoin_shift_px = shift_px;
  rejoin_first_ = -1;
  loop_ba_pending_ = true;
  return true;
}

}  // namespace dsm
