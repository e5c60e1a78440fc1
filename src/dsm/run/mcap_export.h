// SPDX-License-Identifier: MIT
// A run's results as one MCAP file that Foxglove and the ROS 2 tools open (`dsm run --mcap FILE`;
// bag/mcap_writer.h), ROS 2 messages in CDR with their ros2msg schemas, stamped with the frames'
// times:
//   /dsm/camera_pose      geometry_msgs/msg/PoseStamped  each tracked frame's pose (frames.tum)
//   /tf                   tf2_msgs/msg/TFMessage         the same, as the transform map -> camera
//   /dsm/keyframe_pose    geometry_msgs/msg/PoseStamped  each keyframe's pose (keyframes.tum)
//   /dsm/keyframe_image   sensor_msgs/msg/Image          each keyframe's image (mono8, undistorted,
//                                                        photometrically corrected), frame camera
//   /dsm/camera_info      sensor_msgs/msg/CameraInfo     the undistorted pinhole camera, with each
//                                                        keyframe image
//   /dsm/map              sensor_msgs/msg/PointCloud2    the map's points (x y z intensity,
//                                                        float32), at the last pose
//   /dsm/trajectory       nav_msgs/msg/Path              the keyframes' poses, at the last pose
// Poses are camera to world (world_from_cam) in frame "map", the camera frame "camera". A run with
// several maps puts map K (K >= 1) under /dsm/map_K/... with frames "map_K" and "camera_K".
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/geometry/trajectory.h"
#include "dsm/image/image.h"
#include "dsm/io/ply.h"
#include "dsm/map/map.h"

namespace dsm {

// One map's results.
struct McapMap {
  int id = 0;  // The map's number in the run (0: the first).
  Trajectory frames, keyframes;
  PlyCloud points;
  std::vector<std::pair<int64_t, Image<uint8_t>>> keyframe_images;  // Stamp, image.
};

// The images of `map`'s keyframes that have one (retired ones do not), in keyframe order.
std::vector<std::pair<int64_t, Image<uint8_t>>> KeyframeImages(const Map& map);

// Writes `maps` to `path`; throws InputError naming the file when it cannot be written. Returns
// the number of messages written on each topic.
std::vector<std::pair<std::string, int>> WriteRunMcap(const std::filesystem::path& path,
                                                      const std::vector<McapMap>& maps, const PinholeCamera& camera);

}  // namespace dsm
