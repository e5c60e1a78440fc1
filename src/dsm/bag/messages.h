// SPDX-License-Identifier: MIT
// The ROS messages dsm reads, decoded from either wire format (wire.h). Each decoder reads the
// fields in the definition's order and throws InputError naming the message when it is cut short
// or malformed.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dsm/bag/wire.h"
#include "dsm/lie/se3.h"

namespace dsm {

// sensor_msgs/Image; `data` points into the serialized message.
struct ImageMessage {
  int64_t stamp_ns = 0;
  std::string frame_id;
  uint32_t height = 0, width = 0, step = 0;
  std::string encoding;
  bool big_endian = false;
  const uint8_t* data = nullptr;
  size_t size = 0;
};
ImageMessage DecodeImage(WireReader& in);

// sensor_msgs/CompressedImage; `data` points into the serialized message.
struct CompressedImageMessage {
  int64_t stamp_ns = 0;
  std::string frame_id;
  std::string format;  // "jpeg", "png", "mono8; jpeg compressed mono8", ...
  const uint8_t* data = nullptr;
  size_t size = 0;
};
CompressedImageMessage DecodeCompressedImage(WireReader& in);

// sensor_msgs/CameraInfo (the fields dsm uses).
struct CameraInfoMessage {
  int64_t stamp_ns = 0;
  std::string frame_id;
  uint32_t height = 0, width = 0;
  std::string distortion_model;  // plumb_bob, rational_polynomial, equidistant, ...
  std::vector<double> d;
  std::array<double, 9> k{};  // Row-major 3x3.
  uint32_t binning_x = 0, binning_y = 0;
  uint32_t roi_x = 0, roi_y = 0, roi_height = 0, roi_width = 0;
};
CameraInfoMessage DecodeCameraInfo(WireReader& in);

// A pose in time from any of the pose-carrying types: geometry_msgs/PoseStamped,
// PoseWithCovarianceStamped, TransformStamped, nav_msgs/Odometry. `pose` is parent_from_child:
// the child frame's (child_frame_id, or the tracked body) pose in the header's frame.
struct StampedPose {
  int64_t stamp_ns = 0;
  std::string parent;  // header.frame_id
  std::string child;   // child_frame_id; empty for the PoseStamped types
  SE3d pose;
};
// Whether DecodePoses reads messages of `type` ("geometry_msgs/PoseStamped", ...,
// "tf2_msgs/TFMessage").
bool IsPoseType(const std::string& type);
// The poses in one message of `type` (one, or a TFMessage's transforms); throws InputError for a
// type IsPoseType refuses.
std::vector<StampedPose> DecodePoses(const std::string& type, WireReader& in);

}  // namespace dsm
