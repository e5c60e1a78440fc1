// SPDX-License-Identifier: MIT
// A recording's camera topic as a dataset (io/dataset.h).
//   frames        the messages of one sensor_msgs/Image or CompressedImage topic (`topic`, or the
//                 only image topic), stamped with their header stamps. Opening reads the index and
//                 the first and last message: where their header stamps equal their log times
//                 (a recording written from a dataset) every frame takes its log time; otherwise
//                 (a recording made live, stamped at capture and logged later) every message's
//                 header is read once. Images are read as the run takes them.
//   calibration   `calib`: a camera.yaml (io/calibration_io.h) or EuRoC's sensor.yaml (whose T_BS
//                 is the camera's pose on the tracked body); without it, the first
//                 sensor_msgs/CameraInfo of the image topic's camera (`<namespace>/camera_info`,
//                 or the only CameraInfo topic): plumb_bob, rational_polynomial without its
//                 k4..k6, equidistant
//   ground truth  the poses on `gt_topic` (bag_ground_truth.h), or the transform chain
//                 `gt_parent` -> `gt_child` on /tf and /tf_static: the tracked body's poses, turned
//                 into camera poses with T_BS when sensor.yaml gave the calibration (under the
//                 reading `gt` of io/dataset.h), else taken as the camera's
#pragma once

#include <filesystem>
#include <string>

#include "dsm/bag/bag_file.h"
#include "dsm/io/dataset.h"

namespace dsm {

struct BagInput {
  std::string topic;                 // Empty: the only image topic.
  std::filesystem::path calib;       // Empty: the recording's CameraInfo.
  std::string gt_topic;              // Empty: no ground truth from a topic.
  std::string gt_parent, gt_child;   // Both or neither.
  GroundTruthConvention gt;
};

// Throws InputError naming the file and topic when the topic is missing or not an image, when no
// calibration is found, or when a frame's size differs from the calibration's.
Dataset OpenBag(const std::filesystem::path& path, const BagInput& input);

// Whether the recording has a sensor_msgs/Image or CompressedImage topic.
bool HasImageTopic(const BagFile& bag);

// The ground truth `input` names (gt_topic, or the chain gt_parent -> gt_child) as it is in the
// recording: the tracked body's poses (empty when it names none). Throws InputError as
// bag_ground_truth.h.
Trajectory ReadBagGroundTruth(const BagFile& bag, const BagInput& input);

// One line per topic: its name, type and message count (what `dsm info` prints for a recording).
std::string DescribeBagTopics(const BagFile& bag);

}  // namespace dsm
