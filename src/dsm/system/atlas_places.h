// SPDX-License-Identifier: MIT
// The place index of a run's maps (system/atlas.h): the bag of words of every keyframe of every
// map, and the maps a new keyframe of the current map is compared with for a merge. Loop closure
// asks it for places of the keyframe's own map, map merging for places of the merge candidates;
// either verifies a place it finds through the map's PlaceMap, never through another System.
//
// A map joins the index when its mapping side is made and leaves it when that is destroyed; a
// System alone (no Atlas) has an index of its own. The index is read and written by the current
// map's mapping side, and by the Atlas's thread while that mapping side is idle.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "dsm/map/map.h"
#include "dsm/place/place_index.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"

namespace dsm {

// What a place's verification reads of the map that has it (MappingSide implements it).
class PlaceMap {
 public:
  virtual const Map& map() const = 0;
  // Keyframe k's ORB features (computed on first use), and the points it sees (hosted, or an
  // inlier observation) projected into it.
  virtual const OrbFeatures& KeyframeFeatures(int k) = 0;
  virtual std::vector<ReferencePoint> PointsSeenIn(int k) = 0;

 protected:
  ~PlaceMap() = default;
};

class AtlasPlaces {
 public:
  void Join(PlaceMap* map);
  void Leave(PlaceMap* map);  // Its places go; it stops being a merge candidate.
  void Add(PlaceMap* map, int keyframe, BowVector bow);
  void Remove(PlaceMap* map, int keyframe);
  const BowVector* Bow(const PlaceMap* map, int keyframe) const;  // Null when not added.
  // Keyframes of `map` as PlaceIndex::Query gives them: (score, keyframe), best first.
  std::vector<std::pair<double, int>> Query(const PlaceMap* map, const BowVector& bow, double min_score,
                                            const std::function<bool(int)>& excluded) const;
  // The maps the current map's new keyframes are compared with for a merge, in the order given,
  // each with the Atlas's id for it and the serial number it joined with (never reused).
  struct Candidate {
    int id = -1;
    PlaceMap* map = nullptr;
    int serial = -1;
  };
  void SetMergeCandidates(const std::vector<std::pair<int, PlaceMap*>>& candidates);
  const std::vector<Candidate>& merge_candidates() const { return candidates_; }
  // `from`'s places become `into`'s, their keyframe ids shifted by `offset` (a merge).
  void MoveInto(PlaceMap* from, PlaceMap* into, int offset);

 private:
  struct Places {
    int serial = -1;
    PlaceIndex index;
  };
  std::map<const PlaceMap*, Places> maps_;  // Looked up only: the order of maps never counts.
  int next_serial_ = 0;
  std::vector<Candidate> candidates_;
};

}  // namespace dsm
