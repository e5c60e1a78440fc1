// SPDX-License-Identifier: MIT
// Pairing the poses of two trajectories before comparing them.
#pragma once

#include <vector>

#include "dsm/geometry/trajectory.h"

namespace dsm {

struct Association {
  std::vector<size_t> ref_index;
  std::vector<size_t> est_index;
  size_t size() const { return ref_index.size(); }
};

// For every pose of the shorter trajectory (the estimate when both are equally long), the pose of
// the other with the nearest timestamp, kept when |dt| <= max_dt_s. A pose of the longer one may be
// used more than once. Pairs come in the order of the shorter trajectory.
Association AssociateByTime(const Trajectory& ref, const Trajectory& est, double max_dt_s);

// Pose i with pose i; throws InputError when the sizes differ (`ref_name`, `est_name` in the message).
Association AssociateByIndex(const Trajectory& ref, const Trajectory& est, const std::string& ref_name,
                             const std::string& est_name);

}  // namespace dsm
