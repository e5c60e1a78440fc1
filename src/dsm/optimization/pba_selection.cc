// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba_selection.h"

#include <algorithm>
#include <utility>

namespace dsm {

PbaSelection SelectPbaProblem(const Map& map, const std::vector<int>& active, const std::vector<int>& held,
                              const PbaOptions& options) {
  PbaSelection s;
  std::vector<int> index(map.NumKeyframes(), -1);
  std::vector<bool> is_active(map.NumKeyframes(), false), is_held(map.NumKeyframes(), false);
  for (int id : held) is_held[id] = true;
  for (int id : active) {
    is_active[id] = true;
    if (index[id] >= 0) continue;
    index[id] = static_cast<int>(s.cams.size());
    s.cams.push_back(id);
    s.fixed.push_back(id == 0 || is_held[id] || map.keyframe(id).frozen);
  }
  const size_t num_active = s.cams.size();
  // The observations that may enter the problem, per point of the active keyframes: f(host
  // index, point id, observations). A point of a held keyframe: its observations in keyframes
  // outside the window join two fixed poses and constrain only its depth; the newest few suffice.
  const auto for_each_point = [&](const auto& f) {
    std::vector<const Observation*> kept;
    for (size_t c = 0; c < num_active; ++c) {
      const bool frozen = map.keyframe(s.cams[c]).frozen;
      const auto usable = [&](const Observation& o) { return !o.outlier && !(frozen && map.keyframe(o.target).frozen); };
      for (int pid : map.keyframe(s.cams[c]).points) {
        const Point& p = map.point(pid);
        if (p.removed) continue;
        int skip = 0;
        if (is_held[s.cams[c]]) {
          for (const Observation& o : p.observations) skip += usable(o) && !is_active[o.target];
          skip -= options.max_outside_observations;  // The oldest ones are left out.
        }
        kept.clear();
        for (const Observation& o : p.observations)
          if (usable(o) && (is_active[o.target] || skip-- <= 0)) kept.push_back(&o);
        f(c, pid, kept);
      }
    }
  };
  // Keyframes outside the window enter fixed, at most `max_outside_keyframes` of them: those
  // with the most observations (the newer on ties). The rest of the map keeps its observations
  // but sits this solve out, so the problem does not grow with the map.
  std::vector<bool> outside_ok(map.NumKeyframes(), true);
  if (options.max_outside_keyframes > 0) {
    std::vector<int> count(map.NumKeyframes(), 0);
    for_each_point([&](size_t, int, const std::vector<const Observation*>& obs) {
      for (const Observation* o : obs) count[o->target] += !is_active[o->target];
    });
    std::vector<int> outside;
    for (int k = 0; k < map.NumKeyframes(); ++k)
      if (count[k] > 0) outside.push_back(k);
    std::stable_sort(outside.begin(), outside.end(),
                     [&](int a, int b) { return count[a] != count[b] ? count[a] > count[b] : a > b; });
    for (size_t i = options.max_outside_keyframes; i < outside.size(); ++i) outside_ok[outside[i]] = false;
  }
  for_each_point([&](size_t c, int pid, const std::vector<const Observation*>& obs) {
    PbaSelection::PointObservations po;
    po.id = pid;
    po.host = static_cast<int>(c);
    for (const Observation* o : obs) {
      if (!outside_ok[o->target]) continue;
      if (index[o->target] < 0) {  // Observed but not active: in the problem, fixed.
        index[o->target] = static_cast<int>(s.cams.size());
        s.cams.push_back(o->target);
        s.fixed.push_back(true);
      }
      po.targets.push_back(index[o->target]);
    }
    if (!po.targets.empty()) {
      s.num_observations += static_cast<int>(po.targets.size());
      s.points.push_back(std::move(po));
    }
  });
  // A camera tied to the rest by few observations is nearly free (its motion barely changes
  // the energy): it stays fixed in this solve instead of taking a wild step.
  std::vector<int> links(s.cams.size(), 0);
  for (const PbaSelection::PointObservations& po : s.points) {
    links[po.host] += static_cast<int>(po.targets.size());
    for (int t : po.targets) ++links[t];
  }
  // So is one tied by far fewer than placed it before: the observations that did are not in
  // this problem (a keyframe that hosts almost no points, placed by the old map's points, keeps
  // a window slot after those points left the window), and the few left can only pull it away.
  for (size_t c = 0; c < s.cams.size(); ++c) {
    const double placed = map.keyframe(s.cams[c]).most_pba_links;
    if (links[c] < options.min_camera_observations || links[c] < options.min_link_ratio * placed) s.fixed[c] = true;
  }
  s.links = std::move(links);
  return s;
}

}  // namespace dsm
