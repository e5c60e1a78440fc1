// SPDX-License-Identifier: MIT
#include "dsm/run/map_export.h"

#include "dsm/mapping/map_points.h"

namespace dsm {

PlyCloud MapPointCloud(const Map& map, const PinholeCamera& camera) {
  PlyCloud cloud;
  std::vector<int32_t> host, observations;
  for (const LivePoint& p : LivePoints(map, camera)) {
    cloud.xyz.push_back(p.world);
    cloud.rgb.push_back({p.grey, p.grey, p.grey});
    host.push_back(p.host);
    observations.push_back(p.observations);
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
