// SPDX-License-Identifier: MIT
// The mapping side's map handed to a map file (TakeStoredMap) and taken up from one (RestoreMap), and
// the temporary keyframes of a localisation in it (RetireTemporaries).
#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>

#include "dsm/system/mapping_side.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {

StoredMap MappingSide::TakeStoredMap(double residual_level, double texture_level) {
  StoredMap stored;
  if (localizing_) {
    // The loaded map as it was taken up: what the run added goes, the frozen rest is unchanged.
    stored = std::move(loaded_as_);
    map_.KeepFirst(loaded_keyframes_, loaded_point_ids_);
  } else {
    // A map kept for later sessions is adjusted whole once (unless the run did so already): the
    // window leaves each part of it where the adjustments of its time put it, and a whole-map
    // adjustment, which the loop's later keyframes pull into agreement, removes most of the drift
    // a later session would otherwise be held to (docs/results.md, section `sessions`).
    if (stats_->global_ba_ms < 0.0) RunGlobalBundleAdjustment();
    std::vector<std::vector<int>> covisibility = loaded_covisibility_;
    for (const MappingStats::KeyframeLog& log : stats_->per_keyframe) covisibility.push_back(log.covisible);
    covisibility.resize(std::min<size_t>(covisibility.size(), map_.NumKeyframes()));
    // Retired keyframes (culled) are not part of the map kept: the rest are numbered anew.
    const std::vector<int> id = map_.DropRetired();
    const auto renumber = [&id](const std::vector<int>& ids) {
      std::vector<int> out;
      for (int k : ids)
        if (id[k] >= 0) out.push_back(id[k]);
      return out;
    };
    stored.window = renumber(window_);
    stored.covisible = renumber(covisible_);
    for (size_t k = 0; k < covisibility.size(); ++k)
      if (id[k] >= 0) stored.covisibility.push_back(renumber(covisibility[k]));
    stored.image_noise_sigma = std::max(0.0, stats_->image_noise_sigma);
    stored.residual_level = residual_level;
    stored.texture_level = texture_level;
  }
  stored.map = std::move(map_);
  map_ = Map();
  window_.clear();
  covisible_.clear();
  return stored;
}

int MappingSide::RestoreMap(StoredMap* stored_map, bool localize) {
  StoredMap& stored = *stored_map;
  DSM_CHECK(map_.NumKeyframes() == 0, "a map is taken up by a new System, before its first frame");
  DSM_CHECK(stored.map.NumKeyframes() > 0, "a restored map has keyframes");
  localizing_ = localize;
  if (localizing_)
    for (int k = 0; k < stored.map.NumKeyframes(); ++k) stored.map.keyframe(k).frozen = true;
  map_ = std::move(stored.map);
  stored.map = Map();
  loaded_point_ids_ = map_.NumPoints();
  ChooseNoiseHandling(stored.image_noise_sigma);
  window_ = stored.window;
  covisible_ = stored.covisible;
  if (options_.mode == MapMode::kSlidingWindow) {
    window_.insert(window_.end(), covisible_.begin(), covisible_.end());
    covisible_.clear();
  }
  loaded_keyframes_ = map_.NumKeyframes();
  loaded_points_ = map_.NumLivePoints();
  loaded_covisibility_ = stored.covisibility;
  loaded_covisibility_.resize(loaded_keyframes_);

  // The camera's speed per frame as the map has it: the median step between consecutive
  // keyframes over the frames between them.
  std::vector<double> speeds;
  for (int k = 1; k < loaded_keyframes_; ++k) {
    const Keyframe& a = map_.keyframe(k - 1);
    const Keyframe& b = map_.keyframe(k);
    const int frames = b.frame_index - a.frame_index;
    if (frames > 0) speeds.push_back((b.Centre() - a.Centre()).norm() / frames);
  }
  loaded_speed_ = speeds.empty() ? 0.0 : Median(speeds);

  // The newest keyframe of the window is the reference lost frames are tried against first (with
  // those most like each frame), as for a camera lost from it.
  const int ref = window_.empty() ? loaded_keyframes_ - 1 : window_.back();
  Republish(MakeReference(ref, PointsSeenIn(ref), map_.keyframe(ref).PyramidOrRebuilt()));
  // The keyframes' ORB features, which relocalisation ranks and poses candidates by, are computed
  // now rather than on first use: the first frames of the run search the whole map, and a live
  // camera would drop frames while they are computed.
  std::vector<OrbFeatures> features(loaded_keyframes_);
  tbb::parallel_for(0, loaded_keyframes_, [&](int k) { features[k] = DetectOrbFeatures(map_.keyframe(k).Level0(), {}); });
  for (int k = 0; k < loaded_keyframes_; ++k) keyframe_features_.emplace(k, std::move(features[k]));
  // Loop closure recognises the loaded map's places as well as the run's own.
  if (LoopClosureActive())
    for (int k = 0; k < loaded_keyframes_; ++k) AddToPlaceIndex(k);
  if (localizing_) loaded_as_ = std::move(stored);  // All but its map, given back by TakeStoredMap.
  return ref;
}

void MappingSide::RetireTemporaries(int newest) {
  const auto in = [](const std::vector<int>& v, int k) { return std::find(v.begin(), v.end(), k) != v.end(); };
  if (std::none_of(covisible_.begin(), covisible_.end(), [&](int k) { return map_.keyframe(k).frozen; })) return;
  for (int k = loaded_keyframes_; k < newest; ++k) {
    if (map_.keyframe(k).retired || in(window_, k) || in(covisible_, k)) continue;
    map_.Retire(k);
    candidates_.erase(k);
    keyframe_features_.erase(k);
    places_->Remove(this, k);
    ++retired_keyframes_;
  }
}

}  // namespace dsm
