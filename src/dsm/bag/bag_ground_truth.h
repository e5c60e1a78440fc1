// SPDX-License-Identifier: MIT
// Ground truth from a recording: the poses of one topic, or a chain of transforms on /tf and
// /tf_static.
//   topic  geometry_msgs/PoseStamped, PoseWithCovarianceStamped, TransformStamped or
//          nav_msgs/Odometry: each message's pose (child in header.frame_id), at its header stamp
//   chain  parent_from_child composed along the tf tree (frame names without a leading '/'):
//          /tf_static's links are fixed; the moving link with the most messages sets the stamps
//          and the other moving links are interpolated at them (a stamp outside one of their
//          spans gives no pose)
// Every message of the topics involved is read.
#pragma once

#include <string>

#include "dsm/bag/bag_file.h"
#include "dsm/geometry/trajectory.h"

namespace dsm {

// The poses on `topic`, in stamp order. Throws InputError naming the file and topic for a missing
// topic, a type without poses (a TFMessage topic needs ReadTfChain), or no pose at all.
Trajectory ReadPoseTopic(const BagFile& bag, const std::string& topic);

// parent_from_child over time along /tf (or `tf_topic`) and /tf_static. Throws InputError naming
// the file and frames when no chain joins them.
Trajectory ReadTfChain(const BagFile& bag, const std::string& parent, const std::string& child,
                       const std::string& tf_topic = "/tf");

}  // namespace dsm
