// SPDX-License-Identifier: MIT
// Keyframe culling (SystemOptions::keyframe_culling): a keyframe of a place the map already covers
// leaves it once it leaves the temporal window.
#include <algorithm>
#include <limits>
#include <vector>

#include "dsm/mapping/projection.h"
#include "dsm/system/mapping_side.h"

namespace dsm {

namespace {

constexpr double kCoveredShare = 0.9;  // Of the points it sees, seen by kOtherViews other keyframes.
constexpr int kOtherViews = 3;
constexpr double kMaxHostedShare = 0.1;  // Of the points it sees, hosted by it.
constexpr double kMinOldShare = 0.5;     // Of the points it sees, hosted by the older map.

}  // namespace

bool MappingSide::CullKeyframe(int k) {
  if (k == 0 || k < loaded_keyframes_ || map_.keyframe(k).retired) return false;
  // The points it sees: hosted, or an inlier observation in it; covered: three other keyframes
  // see it as well (the host counts, k does not); old: hosted by a keyframe a whole window older
  // than k (the older map, seen again, not the part mapped with k).
  const int window = options_.window.temporal_keyframes + options_.window.covisible_keyframes;
  int seen = 0, covered = 0, hosted = 0, old = 0;
  for (int pid = 0; pid < map_.NumPoints(); ++pid) {
    const Point& p = map_.point(pid);
    if (p.removed) continue;
    const Observation* o = p.FindObservation(k);
    const bool is_host = p.host == k;
    if (!is_host && (o == nullptr || o->outlier)) continue;
    ++seen;
    hosted += is_host;
    // The host's view and the good observations, less k's own: the good observations' count.
    covered += p.NumGoodObservations() >= kOtherViews;
    old += p.host < k - window;
  }
  if (seen == 0 || covered < kCoveredShare * seen || hosted > kMaxHostedShare * seen || old < kMinOldShare * seen)
    return false;

  // Each hosted point goes to the keyframe outside the temporal window that sees it from nearest
  // k's centre, where it projects: the window's adjustment is left as it was (a point re-hosted
  // there would enter it with a free depth).
  const Eigen::Vector3d centre = map_.keyframe(k).Centre();
  const std::vector<int> points = map_.keyframe(k).points;
  for (int pid : points) {
    const Point& p = map_.point(pid);
    if (p.removed) continue;
    int best = -1;
    double best_distance = std::numeric_limits<double>::infinity();
    Eigen::Vector2f pixel;
    float idepth = 0.f;
    for (const Observation& o : p.observations) {
      if (o.outlier || map_.keyframe(o.target).retired ||
          std::find(window_.begin(), window_.end(), o.target) != window_.end())
        continue;
      Eigen::Vector2f px;
      float rho;
      const double distance = (map_.keyframe(o.target).Centre() - centre).norm();
      if (distance < best_distance && ProjectPoint(map_, camera_, p, o.target, 4.f, &px, &rho)) {
        best = o.target;
        best_distance = distance;
        pixel = px;
        idepth = rho;
      }
    }
    if (best < 0) {
      map_.point(pid).removed = true;
      ++stats_->points_dropped;
      continue;
    }
    map_.LoadPyramids({best});
    map_.Rehost(pid, best, pixel, idepth);
    ++stats_->points_rehosted;
  }
  map_.Retire(k);
  keyframe_features_.erase(k);
  places_->Remove(this, k);
  ++stats_->keyframes_culled;
  return true;
}

void MappingSide::CullUnusedKeyframes(const std::vector<int>& in_use) {
  std::vector<int> still;
  for (int k : cull_pending_) {
    const bool used = std::find(in_use.begin(), in_use.end(), k) != in_use.end() ||
                      std::find(covisible_.begin(), covisible_.end(), k) != covisible_.end() ||
                      std::find(window_.begin(), window_.end(), k) != window_.end();
    if (used) {
      still.push_back(k);
    } else {
      CullKeyframe(k);
    }
  }
  cull_pending_ = std::move(still);
}

}  // namespace dsm
