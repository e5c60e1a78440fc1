// SPDX-License-Identifier: MIT
#include "dsm/place/place_index.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace dsm {

void PlaceIndex::Add(int keyframe, BowVector bow) {
  Remove(keyframe);
  for (const auto& [word, weight] : bow) {
    if (word >= static_cast<int>(inverted_.size())) inverted_.resize(word + 1);
    inverted_[word].emplace_back(keyframe, weight);
  }
  bows_[keyframe] = std::move(bow);
}

void PlaceIndex::Remove(int keyframe) {
  const auto it = bows_.find(keyframe);
  if (it == bows_.end()) return;
  for (const auto& [word, weight] : it->second)
    std::erase_if(inverted_[word], [keyframe](const auto& entry) { return entry.first == keyframe; });
  bows_.erase(it);
}

const BowVector* PlaceIndex::Bow(int keyframe) const {
  const auto it = bows_.find(keyframe);
  return it == bows_.end() ? nullptr : &it->second;
}

std::vector<std::pair<double, int>> PlaceIndex::Query(const BowVector& bow, double min_score,
                                                      const std::function<bool(int)>& excluded) const {
  // Vocabulary::Score summed over the shared words: 0.5 * sum (a_w + b_w - |a_w - b_w|).
  std::unordered_map<int, double> sums;
  for (const auto& [word, a] : bow) {
    if (word >= static_cast<int>(inverted_.size())) continue;
    for (const auto& [keyframe, b] : inverted_[word]) sums[keyframe] += a + b - std::abs(a - b);
  }
  std::vector<std::pair<double, int>> scored;
  for (const auto& [keyframe, sum] : sums)
    if (0.5 * sum >= min_score && !excluded(keyframe)) scored.emplace_back(0.5 * sum, keyframe);
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  return scored;
}

}  // namespace dsm
