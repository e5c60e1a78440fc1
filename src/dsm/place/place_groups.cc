// SPDX-License-Identifier: MIT
#include "dsm/place/place_groups.h"

#include <algorithm>

namespace dsm {

std::vector<int> ConsistentGroups(const std::vector<std::pair<double, int>>& scored, int consistent,
                                  std::vector<PlaceGroup>* previous, int* newly_found) {
  struct Group {
    int lo, hi, best;
    double score;
  };
  std::vector<Group> groups;
  for (const auto& [score, k] : scored) {
    Group g{k - PlaceGroups::kReach, k + PlaceGroups::kReach, k, 0.0};
    for (const auto& [s2, k2] : scored)
      if (k2 >= g.lo && k2 <= g.hi) g.score += s2;
    groups.push_back(g);
  }
  double best_group = 0.0;
  for (const Group& g : groups) best_group = std::max(best_group, g.score);
  std::erase_if(groups, [&](const Group& g) { return g.score < PlaceGroups::kShare * best_group; });
  std::vector<PlaceGroup> now;
  std::vector<int> found;
  for (const Group& g : groups) {
    int count = 1;
    for (const PlaceGroup& p : *previous)
      if (g.lo <= p.hi && p.lo <= g.hi) count = std::max(count, p.count + 1);
    now.push_back({g.lo, g.hi, count});
    if (count == consistent) ++*newly_found;
    if (count >= consistent) found.push_back(g.best);
  }
  *previous = std::move(now);
  return found;
}

}  // namespace dsm
