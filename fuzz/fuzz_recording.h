// SPDX-License-Identifier: MIT
// What the recordings' fuzz targets share (bag/): the input is a whole recording file, written to
// `file` in the scratch folder. It is opened, every topic's messages (up to 16 each) are read and
// decoded as their type says, and then it is opened as a dataset the way `dsm run` opens it (its
// CameraInfo as the calibration, a pose topic as the ground truth). Only InputError may come out;
// what is accepted keeps the readers' promises.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace dsm::fuzz {

void FuzzRecording(const std::filesystem::path& file, const uint8_t* data, size_t size);
// The same checks on the recording at `recording` as it is (a file or a ROS 2 bag's folder).
void CheckRecording(const std::filesystem::path& recording);

}  // namespace dsm::fuzz
