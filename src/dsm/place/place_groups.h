// SPDX-License-Identifier: MIT
// Consistent place candidates. A place is seen by several keyframes mapped one after another, and
// a returning camera sees it in several keyframes in a row: a single high score is not a place.
// Each candidate keyframe k (with its PlaceIndex::Query score) forms the group of ids
// [k - kReach, k + kReach], scored by the sum of the scores of the candidates in it; groups
// scoring under kShare of the best group are dropped. A group overlapping (in ids) a group the
// keyframe before kept extends that one's run; a run of `consistent` keyframes is a detection.
#pragma once

#include <utility>
#include <vector>

namespace dsm {

struct PlaceGroup {
  int lo = 0, hi = 0;  // Keyframe ids.
  int count = 0;       // Keyframes in a row that found it, this one included.
};

struct PlaceGroups {
  static constexpr int kReach = 3;         // A candidate's group: keyframes this many ids either side.
  static constexpr double kShare = 0.75;   // Groups kept: at least this share of the best group's score.
};

// `scored`: (score, keyframe) candidates of the new keyframe; `previous`: the groups the keyframe
// before kept, replaced by this keyframe's. Returns the best candidate of each group found by
// `consistent` keyframes in a row or more; `newly_found` is incremented per group reaching that
// count now.
std::vector<int> ConsistentGroups(const std::vector<std::pair<double, int>>& scored, int consistent,
                                  std::vector<PlaceGroup>* previous, int* newly_found);

// Whether keyframe `k` is within a group's reach of keyframe `other`.
inline bool InSamePlace(int k, int other) { return k - other <= PlaceGroups::kReach && other - k <= PlaceGroups::kReach; }

}  // namespace dsm
