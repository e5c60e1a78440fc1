// SPDX-License-Identifier: MIT
// CDR bytes (cdr_writer.h) of the ROS 2 camera messages dsm writes, for ros2_schemas.h's
// definitions: a mono8 sensor_msgs/msg/Image and a plumb_bob sensor_msgs/msg/CameraInfo (R the
// identity, P = [K | 0], the whole image as its region of interest).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dsm/image/image.h"

namespace dsm {

std::vector<uint8_t> CdrImage(int64_t t_ns, const std::string& frame, const Image<uint8_t>& image);

// `distortion`: plumb_bob's k1 k2 t1 t2 k3.
std::vector<uint8_t> CdrCameraInfo(int64_t t_ns, const std::string& frame, int width, int height, double fx, double fy,
                                   double cx, double cy, const std::vector<double>& distortion);

}  // namespace dsm
