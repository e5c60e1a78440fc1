// SPDX-License-Identifier: MIT
#include "dsm/mapping/map_points.h"

#include <algorithm>
#include <cmath>

#include "dsm/mapping/projection.h"

namespace dsm {

std::vector<LivePoint> LivePoints(const Map& map, const PinholeCamera& camera) {
  std::vector<LivePoint> out;
  out.reserve(map.NumPoints());
  for (int id = 0; id < map.NumPoints(); ++id) {
    const Point& p = map.point(id);
    if (p.removed) continue;
    const Keyframe& kf = map.keyframe(p.host);
    const int x = std::clamp(static_cast<int>(std::lround(p.pixel.x())), 0, camera.width - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.pixel.y())), 0, camera.height - 1);
    out.push_back({PointInWorld(map, camera, p).cast<float>(),
                   static_cast<uint8_t>(std::clamp(std::lround(kf.Intensity(x, y)), 0L, 255L)), p.host,
                   p.NumGoodObservations()});
  }
  return out;
}

}  // namespace dsm
