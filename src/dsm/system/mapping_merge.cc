// SPDX-License-Identifier: MIT
// Map merging on the mapping side: a map started after a loss (system/atlas.h) recognises a place
// of an earlier map of the run and takes that map in, so that the run ends with one map and one
// trajectory (the frames follow in System::MergeVerified).
//
// Detection and verification are the loop's (mapping_loop.cc: DetectMerge), against the other
// map's place index and keyframes. The merge itself (TakeMerge) moves the other map rigidly,
// with its scale, onto the verified match: two maps joined at one place have no loop between
// them, so a pose graph would move nothing. The seam is then the persistent map's: the next
// keyframes select the merged keyframes as covisible, re-observe their points, and the loop
// bundle adjustment refines both sides together.
#include <algorithm>
#include <chrono>
#include <utility>

#include "dsm/system/mapping_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/util/check.h"

namespace dsm {

int MappingSide::TakeMerge(MappingSide& other, int taken_id) {
  DSM_CHECK(MergeReadyWith(other) && places_ == other.places_, "a merge takes the map its keyframe recognised");
  const auto start = std::chrono::steady_clock::now();
  const LoopState::PendingMerge pending = std::move(*loop_.pending_merge);
  loop_.pending_merge.reset();
  loop_.merge_ready.store(-1);
  const int n = map_.NumKeyframes();
  // S: this world from the other's (a point of the other map x goes to S x here).
  const Sim3d S = Sim3d(map_.keyframe(pending.keyframe).cam_from_world).Inverse() * pending.match.k_from_c *
                  Sim3d(other.map_.keyframe(pending.match.candidate).cam_from_world);
  const Sim3d to_other = S.Inverse();
  const double sigma = to_other.Scale();  // Inverse depths are multiplied by it.
  for (int j = 0; j < other.map_.NumKeyframes(); ++j) {
    const Keyframe& from = other.map_.keyframe(j);
    auto k = std::make_unique<Keyframe>(from);
    k->id = n + j;
    const Sim3d g = Sim3d(from.cam_from_world) * to_other;
    k->cam_from_world = SE3d(g.So3(), g.Translation() / g.Scale());
    if (!from.retired) k->image = from.Level0();
    k->pyramid = nullptr;
    k->points.clear();
    map_.RestoreKeyframe(std::move(k));
    if (n + j >= static_cast<int>(keyframe_scale_.size())) keyframe_scale_.resize(n + j + 1, 1.0);
    keyframe_scale_[n + j] = other.KeyframeScale(j) * sigma;
  }
  for (auto& [k, features] : other.keyframe_features_) keyframe_features_.emplace(n + k, std::move(features));
  int points = 0;
  for (int pid = 0; pid < other.map_.NumPoints(); ++pid) {
    Point p = other.map_.point(pid);
    if (p.removed) continue;
    p.id = map_.NumPoints();
    p.host += n;
    p.created_at_keyframe += n;  // Counts keyframes by id, as the hosts do.
    p.idepth *= static_cast<float>(sigma);
    for (Observation& o : p.observations) o.target += n;
    map_.RestorePoint(std::move(p));
    ++points;
  }
  const int candidate = n + pending.match.candidate;
  loop_.merged_blocks.push_back({n, other.map_.NumKeyframes(), pending.keyframe, candidate, pending.match.k_from_c});
  MappingStats::MapMerge merge;
  merge.frame = map_.keyframe(pending.keyframe).frame_index;
  merge.keyframe = pending.keyframe;
  merge.candidate = candidate;
  merge.map = taken_id;
  merge.keyframes = other.map_.NumKeyframes();
  merge.points = points;
  merge.inliers = pending.match.inliers;
  merge.scale = S.Scale();
  // The other System keeps its stats; its map is this one's now (its frames: System::MergeVerified).
  other.map_ = Map();
  other.keyframe_features_.clear();
  places_->MoveInto(&other, this, n);
  loop_.merge_ba_pending = true;
  merge.ms = internal::MsSince(start);
  stats_->maps_merged.push_back(merge);
  return n;
}

bool MappingSide::AdjustMerge(int newest) {
  if (!loop_.merge_ba_pending) return false;
  const MergedBlock& b = loop_.merged_blocks.back();
  if (std::none_of(covisible_.begin(), covisible_.end(), [&](int k) { return b.Contains(k); })) return false;
  loop_.merge_ba_pending = false;
  // Neither side is the reference: the merged keyframes nearest the match and this map's newest
  // are freed alike (loop_ba_max_keyframes in all, half each); the keyframes that observe their
  // points enter held (pba_selection.h), and hold the rest of both maps where they are.
  const int half = std::max(1, options_.loop_ba_max_keyframes / 2);
  std::vector<int> keyframes;
  for (int k = std::max(b.first, b.candidate - half / 2); k < std::min(b.first + b.count, b.candidate + half / 2 + 1); ++k)
    if (!map_.keyframe(k).retired) keyframes.push_back(k);
  for (int k = newest, n = 0; k >= 0 && n < half; --k)
    if (!b.Contains(k) && !map_.keyframe(k).retired) keyframes.push_back(k), ++n;
  last_loop_ba_ = newest;
  AdjustAfterNewest(std::move(keyframes), {}, LoopBaOptions(), /*seam=*/false);
  return true;
}

}  // namespace dsm
