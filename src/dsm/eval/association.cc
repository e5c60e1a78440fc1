// SPDX-License-Identifier: MIT
#include "dsm/eval/association.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dsm/util/check.h"

namespace dsm {

Association AssociateByTime(const Trajectory& ref, const Trajectory& est, double max_dt_s) {
  DSM_CHECK(ref.HasStamps() && est.HasStamps(), "time association needs stamped trajectories");
  const bool est_longer = est.size() > ref.size();
  const Trajectory& shorter = est_longer ? ref : est;
  const Trajectory& longer = est_longer ? est : ref;
  const int64_t max_dt_ns = std::llround(max_dt_s * 1e9);

  // Indices of the longer trajectory sorted by stamp (stable: ties keep file order).
  std::vector<size_t> order(longer.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return longer.stamps_ns[a] < longer.stamps_ns[b]; });

  Association result;
  for (size_t i = 0; i < shorter.size(); ++i) {
    const int64_t t = shorter.stamps_ns[i];
    const auto it = std::lower_bound(order.begin(), order.end(), t,
                                     [&](size_t idx, int64_t value) { return longer.stamps_ns[idx] < value; });
    // Candidates: the first stamp >= t and the last stamp < t; on a tie the earlier stamp wins.
    size_t best = order.size();
    int64_t best_dt = 0;
    if (it != order.begin()) {
      best = *std::prev(it);
      best_dt = t - longer.stamps_ns[best];
      // Among equal stamps the first in file order.
      auto first = std::lower_bound(order.begin(), order.end(), longer.stamps_ns[best],
                                    [&](size_t idx, int64_t value) { return longer.stamps_ns[idx] < value; });
      best = *first;
    }
    if (it != order.end()) {
      const int64_t dt = longer.stamps_ns[*it] - t;
      if (best == order.size() || dt < best_dt) {
        best = *it;
        best_dt = dt;
      }
    }
    if (best == order.size() || best_dt > max_dt_ns) continue;
    result.ref_index.push_back(est_longer ? i : best);
    result.est_index.push_back(est_longer ? best : i);
  }
  return result;
}

Association AssociateByIndex(const Trajectory& ref, const Trajectory& est, const std::string& ref_name,
                             const std::string& est_name) {
  if (ref.size() != est.size()) {
    throw InputError("trajectories without timestamps pair pose by pose, but " + ref_name + " has " +
                     std::to_string(ref.size()) + " poses and " + est_name + " has " +
                     std::to_string(est.size()));
  }
  Association result;
  result.ref_index.resize(ref.size());
  std::iota(result.ref_index.begin(), result.ref_index.end(), size_t{0});
  result.est_index = result.ref_index;
  return result;
}

}  // namespace dsm
