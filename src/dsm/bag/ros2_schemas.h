// SPDX-License-Identifier: MIT
// The ROS 2 message definitions dsm writes, as an MCAP `ros2msg` schema holds them: the type's
// definition, then each type it uses after a line of '=' and "MSG: pkg/Type" (as rosbag2 writes
// them). Types: geometry_msgs/msg/PoseStamped, tf2_msgs/msg/TFMessage, sensor_msgs/msg/Image,
// sensor_msgs/msg/CameraInfo, sensor_msgs/msg/PointCloud2, nav_msgs/msg/Path.
#pragma once

#include <string>

namespace dsm {

// Throws std::out_of_range for a type not listed above.
std::string Ros2Schema(const std::string& type);

}  // namespace dsm
