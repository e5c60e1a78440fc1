// SPDX-License-Identifier: MIT
#include "dsm/mapping/window.h"

#include <cmath>
#include <limits>

#include "dsm/util/check.h"

namespace dsm {

void WindowOptions::Validate() const {
  if (temporal_keyframes < 2 || temporal_keyframes > 20) throw InputError("window.temporal_keyframes must be within 2..20");
  if (covisible_keyframes < 0 || covisible_keyframes > 20) throw InputError("window.covisible_keyframes must be within 0..20");
  if (!(depleted_distance_px >= 0)) throw InputError("window.depleted_distance_px must be non-negative");
}

double VisibleRatio(const Map& map, int keyframe, int target) {
  int total = 0, seen = 0;
  for (int pid : map.keyframe(keyframe).points) {
    const Point& p = map.point(pid);
    if (p.removed) continue;
    ++total;
    for (const Observation& o : p.observations) seen += o.target == target && !o.outlier;
  }
  return total > 0 ? static_cast<double>(seen) / total : 0.0;
}

int SelectKeyframeToDrop(const Map& map, const std::vector<int>& window, const WindowOptions& options) {
  const int n = static_cast<int>(window.size());
  if (n <= options.temporal_keyframes) return -1;
  const int newest = window.back();
  // Candidates: all but the newest two.
  for (int k = 0; k < n - 2; ++k) {
    const int id = window[k];
    if (VisibleRatio(map, id, newest) < options.min_visible_ratio ||
        std::abs(map.keyframe(id).affine.a - map.keyframe(newest).affine.a) > options.max_affine_change) {
      return id;
    }
  }
  const double eps = 1e-4;
  double best = -1.0;
  int drop = window.front();
  for (int k = 0; k < n - 2; ++k) {
    const Eigen::Vector3d ci = map.keyframe(window[k]).Centre();
    double sum = 0.0;
    for (int j = 0; j < n; ++j) {
      if (j == k) continue;
      sum += 1.0 / ((ci - map.keyframe(window[j]).Centre()).norm() + eps);
    }
    const double score = std::sqrt((ci - map.keyframe(newest).Centre()).norm() + eps) * sum;
    if (score > best) best = score, drop = window[k];
  }
  return drop;
}

}  // namespace dsm
