// SPDX-License-Identifier: MIT
// A trajectory: camera-to-world poses (world_from_cam), optionally stamped in integer nanoseconds.
#pragma once

#include <cstdint>
#include <vector>

#include "dsm/lie/se3.h"

namespace dsm {

struct Trajectory {
  std::vector<int64_t> stamps_ns;  // Empty for unstamped formats (KITTI): poses pair by index.
  std::vector<SE3d> poses;         // world_from_cam.

  size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  bool HasStamps() const { return !stamps_ns.empty(); }

  void Add(int64_t t_ns, const SE3d& world_from_cam) {
    stamps_ns.push_back(t_ns);
    poses.push_back(world_from_cam);
  }

  // Total distance travelled by the camera centres, in metres.
  double PathLength() const {
    double length = 0.0;
    for (size_t i = 1; i < poses.size(); ++i) {
      length += (poses[i].Translation() - poses[i - 1].Translation()).norm();
    }
    return length;
  }
};

}  // namespace dsm
