// SPDX-License-Identifier: MIT
#include "dsm/mapping/covisibility.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "dsm/mapping/projection.h"

namespace dsm {

CovisibleSelection SelectCovisibleKeyframes(const Map& map, const PinholeCamera& camera, const std::vector<int>& temporal,
                                            const WindowOptions& options, DistanceMap* distance) {
  CovisibleSelection out;
  std::vector<CovisibleChoice>& chosen = out.chosen;
  if (options.covisible_keyframes <= 0 || temporal.empty()) return out;
  const int newest = temporal.back();
  std::vector<int> old;
  for (int k = 0; k < map.NumKeyframes(); ++k)
    if (!map.keyframe(k).retired && std::find(temporal.begin(), temporal.end(), k) == temporal.end()) old.push_back(k);

  // Projections of every old keyframe's usable points into the newest keyframe (independent per
  // keyframe: parallel and deterministic).
  struct Projected {
    int live_points = 0;
    std::vector<int> ids;
    std::vector<Eigen::Vector2f> pixels;
    std::vector<bool> same_scale;  // Seen at a similar distance by the host and the newest keyframe.
  };
  std::vector<Projected> projected(old.size());
  tbb::parallel_for(size_t{0}, old.size(), [&](size_t i) {
    Projected& mine = projected[i];
    for (int pid : map.keyframe(old[i]).points) {
      const Point& p = map.point(pid);
      if (p.removed) continue;
      ++mine.live_points;
      Eigen::Vector2f px;
      float rho;
      if (ProjectPoint(map, camera, p, newest, 0.f, &px, &rho) &&
          ViewAngleDeg(map, camera, p, newest) <= options.max_view_angle_deg) {
        mine.ids.push_back(pid);
        mine.pixels.push_back(px);
        const float scale = rho / p.idepth;  // Distance in the host over distance in the newest keyframe.
        mine.same_scale.push_back(scale <= options.max_scale_change && scale >= 1.f / options.max_scale_change);
      }
    }
  });

  std::vector<bool> taken(old.size(), false);
  while (static_cast<int>(chosen.size()) < options.covisible_keyframes) {
    int best = -1, best_count = 0;
    for (size_t i = 0; i < old.size(); ++i) {
      if (taken[i] || projected[i].live_points == 0) continue;
      int count = 0;
      for (const Eigen::Vector2f& px : projected[i].pixels) count += distance->Distance(px) >= options.depleted_distance_px;
      if (count <= options.min_covisible_ratio * projected[i].live_points) continue;
      if (count > best_count) best = static_cast<int>(i), best_count = count;
    }
    if (best < 0) break;
    taken[best] = true;
    chosen.push_back({old[best], best_count});
    for (const Eigen::Vector2f& px : projected[best].pixels) distance->Add(px);
  }
  for (size_t i = 0; i < old.size(); ++i) {
    if (taken[i]) continue;
    for (size_t j = 0; j < projected[i].pixels.size(); ++j)
      if (projected[i].same_scale[j]) {
        out.other_old_points.push_back(projected[i].ids[j]);
        out.other_old_pixels.push_back(projected[i].pixels[j]);
      }
  }
  return out;
}

}  // namespace dsm
