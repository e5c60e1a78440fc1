// SPDX-License-Identifier: MIT
#include "dsm/system/atlas_places.h"

#include <algorithm>

#include "dsm/util/check.h"

namespace dsm {

void AtlasPlaces::Join(PlaceMap* map) {
  DSM_CHECK(!maps_.count(map), "a map joins the place index once");
  maps_[map].serial = next_serial_++;
}

void AtlasPlaces::Leave(PlaceMap* map) {
  maps_.erase(map);
  std::erase_if(candidates_, [&](const Candidate& c) { return c.map == map; });
}

void AtlasPlaces::Add(PlaceMap* map, int keyframe, BowVector bow) {
  const auto it = maps_.find(map);
  DSM_CHECK(it != maps_.end(), "a map adds places once it joined the index");
  it->second.index.Add(keyframe, std::move(bow));
}

void AtlasPlaces::Remove(PlaceMap* map, int keyframe) {
  const auto it = maps_.find(map);
  if (it != maps_.end()) it->second.index.Remove(keyframe);
}

const BowVector* AtlasPlaces::Bow(const PlaceMap* map, int keyframe) const {
  const auto it = maps_.find(map);
  return it == maps_.end() ? nullptr : it->second.index.Bow(keyframe);
}

std::vector<std::pair<double, int>> AtlasPlaces::Query(const PlaceMap* map, const BowVector& bow, double min_score,
                                                       const std::function<bool(int)>& excluded) const {
  const auto it = maps_.find(map);
  if (it == maps_.end()) return {};
  return it->second.index.Query(bow, min_score, excluded);
}

void AtlasPlaces::SetMergeCandidates(const std::vector<std::pair<int, PlaceMap*>>& candidates) {
  candidates_.clear();
  for (const auto& [id, map] : candidates) {
    const auto it = maps_.find(map);
    DSM_CHECK(it != maps_.end(), "a merge candidate joined the place index");
    candidates_.push_back({id, map, it->second.serial});
  }
}

void AtlasPlaces::MoveInto(PlaceMap* from, PlaceMap* into, int offset) {
  const auto it = maps_.find(from);
  const auto to = maps_.find(into);
  DSM_CHECK(it != maps_.end() && to != maps_.end(), "a merge joins two maps of the place index");
  for (const auto& [keyframe, bow] : it->second.index.bows()) to->second.index.Add(keyframe + offset, bow);
  it->second.index = PlaceIndex();
}

}  // namespace dsm
