// SPDX-License-Identifier: MIT
// The keyframes' bags of words with an inverted index (word -> keyframes that have it), so that a
// query scores only the keyframes that share a word with it (Vocabulary::Score).
#pragma once

#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "dsm/place/vocabulary.h"

namespace dsm {

class PlaceIndex {
 public:
  void Add(int keyframe, BowVector bow);
  void Remove(int keyframe);
  const BowVector* Bow(int keyframe) const;  // Null when not added.
  // (score, keyframe) of every keyframe that scores at least `min_score` against `bow` and is not
  // `excluded`, best first (ties: lower id first).
  std::vector<std::pair<double, int>> Query(const BowVector& bow, double min_score,
                                            const std::function<bool(int)>& excluded) const;
  size_t size() const { return bows_.size(); }
  const std::map<int, BowVector>& bows() const { return bows_; }  // By keyframe id.

 private:
  std::map<int, BowVector> bows_;
  std::vector<std::vector<std::pair<int, float>>> inverted_;  // Per word: (keyframe, weight).
};

}  // namespace dsm
