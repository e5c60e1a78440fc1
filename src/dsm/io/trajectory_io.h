// SPDX-License-Identifier: MIT
// Trajectory files. All poses are read and written as given; for camera trajectories that means
// world_from_cam.
//   tum    "t tx ty tz qx qy qz qw", t in seconds ('#' comments)
//   euroc  "t_ns, px, py, pz, qw, qx, qy, qz[, ...]" (8 or more columns; a ground-truth CSV)
//   kitti  "r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz", no timestamps
#pragma once

#include <filesystem>
#include <string>

#include "dsm/geometry/trajectory.h"

namespace dsm {

enum class TrajectoryFormat { kTum, kEuroc, kKitti };

TrajectoryFormat ParseTrajectoryFormat(const std::string& name, const std::string& where);
std::string TrajectoryFormatName(TrajectoryFormat format);

// From the first data line: commas -> euroc, 12 fields -> kitti, 8 fields -> tum.
TrajectoryFormat DetectTrajectoryFormat(const std::filesystem::path& path);

// A rotation's quaternion, normalised when the pose is made: throws InputError naming `where` when
// it is zero, or so large that its norm overflows (a component of 1e154 squares to infinity, and
// normalising gives no rotation).
void CheckQuaternion(const Eigen::Quaterniond& q, const std::string& where);

// Throws InputError naming the file and line on any malformed row, or when the file is empty.
Trajectory ReadTrajectory(const std::filesystem::path& path, TrajectoryFormat format);

// TUM format with full nanosecond precision in the timestamps.
void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

}  // namespace dsm
