// SPDX-License-Identifier: MIT
// What a System's mapping side keeps for loop closure and map merging (mapping_loop.cc,
// mapping_merge.cc): the candidate runs of the last keyframe and of each map it may merge with,
// and the merges and loops it made (the places themselves: atlas_places.h).
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "dsm/lie/sim3.h"
#include "dsm/place/place_groups.h"
#include "dsm/place/vocabulary.h"

namespace dsm {

class PlaceMap;

// Keyframe kf seeing keyframe `candidate` again (of this map or another): the Sim(3) from the
// candidate's camera to kf's (at each one's scale), the brightness of kf relative to the
// candidate's (a and b; without the exposure times) and the RANSAC inliers.
struct LoopMatch {
  int candidate = -1;
  Sim3d k_from_c;
  double alpha = 0.0, beta = 0.0;
  int inliers = 0;
  double shift_px = 0.0;  // Median move of the candidate's points in kf that the loop makes.
  double depth = 0.0;     // Mean depth of the candidate's points (their scale).
  double residual_ratio = 0.0;  // The direct alignment's median residual over kf's error scale.
  double margin = 0.0;  // The map as it is over the loop in median residual (0: no other fit).
};

// Keyframes merged from another map, ids first .. first + count - 1, with the match that joined
// them (the keyframe, the candidate's id in this map and their Sim(3)): a pose graph joins the
// block to the rest there, not through the ids next to it.
struct MergedBlock {
  int first = 0, count = 0, keyframe = -1, candidate = -1;
  Sim3d k_from_c;
  bool Contains(int k) const { return k >= first && k < first + count; }
};

struct LoopState {
  const Vocabulary* vocabulary = nullptr;  // Null: loop closure off.
  std::unique_ptr<Vocabulary> own_vocabulary;  // LoopClosureOptions::vocabulary's, when given.
  std::vector<PlaceGroup> groups;           // The last keyframe's candidate groups.
  int last_loop_keyframe = -1;              // The keyframe that closed the last loop (-1: none).
  // Map merging: the candidate groups per merge candidate (AtlasPlaces::merge_candidates)
  // (by AtlasPlaces::Candidate::serial) ...
  std::map<int, std::vector<PlaceGroup>> merge_groups;
  // ... the verified match waiting for System::MergeVerified (its map's id in merge_ready once
  // set) ...
  struct PendingMerge {
    const PlaceMap* source = nullptr;
    int keyframe = -1;
    LoopMatch match;
  };
  std::optional<PendingMerge> pending_merge;
  std::atomic<int> merge_ready{-1};
  std::vector<MergedBlock> merged_blocks;  // ... the merges made ...
  bool merge_ba_pending = false;           // ... and whether the last waits for its adjustment.
};

}  // namespace dsm
