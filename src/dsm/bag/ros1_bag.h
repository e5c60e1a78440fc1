// SPDX-License-Identifier: MIT
// A ROS 1 bag (format 2.0) read through ROS 1's bag storage library (bag_file.h).
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/bag/bag_file.h"

namespace dsm {

// Throws InputError naming the file when the library cannot open it as a bag.
std::unique_ptr<BagFile> OpenRos1Bag(const std::filesystem::path& path);

}  // namespace dsm
