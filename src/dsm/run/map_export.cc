// SPDX-License-Identifier: MIT
#include "dsm/run/map_export.h"

#include <algorithm>
#include <cmath>

#include "dsm/mapping/projection.h"

namespace dsm {

PlyCloud MapPointCloud(const Map& map, const PinholeCamera& camera) {
  PlyCloud cloud;
  std::vector<int32_t> host, observations;
  for (int id = 0; id < map.NumPoints(); ++id) {
    const Point& p = map.point(id);
    if (p.removed) continue;
    const Keyframe& kf = map.keyframe(p.host);
    cloud.xyz.push_back(PointInWorld(map, camera, p).cast<float>());
    const int x = std::clamp(static_cast<int>(std::lround(p.pixel.x())), 0, kf.image.width() - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.pixel.y())), 0, kf.image.height() - 1);
    const auto grey = static_cast<uint8_t>(std::clamp(std::lround(kf.Intensity(x, y)), 0L, 255L));
    cloud.rgb.push_back({grey, grey, grey});
    host.push_back(p.host);
    observations.push_back(p.NumGoodObservations());
  }
  cloud.ints = {{"host", std::move(host)}, {"observations", std::move(observations)}};
  cloud.comments = {"dsm map points: world coordinates in the map's own scale (monocular: not metres), grey value of the host pixel"};
  return cloud;
}

PlyCloud KeyframeCloud(const Map& map) {
  PlyCloud cloud;
  std::vector<int32_t> ids, frames;
  for (int id = 0; id < map.NumKeyframes(); ++id) {
    const Keyframe& kf = map.keyframe(id);
    cloud.xyz.push_back(kf.Centre().cast<float>());
    ids.push_back(kf.id);
    frames.push_back(kf.frame_index);
  }
  cloud.ints = {{"keyframe", std::move(ids)}, {"frame", std::move(frames)}};
  cloud.comments = {"dsm keyframes: camera centres in world coordinates"};
  return cloud;
}

}  // namespace dsm
