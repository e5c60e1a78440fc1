// SPDX-License-Identifier: MIT
#include "dsm/io/trajectory_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

TrajectoryFormat ParseTrajectoryFormat(const std::string& name, const std::string& where) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  throw InputError(where + ": unknown trajectory format '" + name + "' (expected tum, euroc or kitti)");
}

std::string TrajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum: return "tum";
    case TrajectoryFormat::kEuroc: return "euroc";
    case TrajectoryFormat::kKitti: return "kitti";
  }
  return "?";
}

TrajectoryFormat DetectTrajectoryFormat(const std::filesystem::path& path) {
  for (const DataRow& row : ReadDataRows(path, " \t")) {
    const bool commas = std::any_of(row.fields.begin(), row.fields.end(),
                                    [](const std::string& f) { return f.find(',') != std::string::npos; });
    if (commas) return TrajectoryFormat::kEuroc;
    const size_t n = row.fields.size();
    if (n == 12) return TrajectoryFormat::kKitti;
    if (n == 8) return TrajectoryFormat::kTum;
    throw InputError(Where(path, row.line) + ": cannot tell the trajectory format from a line of " +
                     std::to_string(n) + " fields (tum has 8, kitti 12, euroc is comma-separated)");
  }
  throw InputError(path.string() + ": the trajectory file has no poses");
}

void CheckQuaternion(const Eigen::Quaterniond& q, const std::string& where) {
  const double norm = q.norm();
  if (norm < 1e-6) throw InputError(where + ": the quaternion is zero");
  if (!std::isfinite(norm) || norm > 1e6) {
    throw InputError(where + ": the quaternion's norm is implausible (" + std::to_string(norm) + ")");
  }
}

Trajectory ReadTrajectory(const std::filesystem::path& path, TrajectoryFormat format) {
  Trajectory traj;
  for (const DataRow& row : ReadDataRows(path, format == TrajectoryFormat::kEuroc ? ", \t" : " \t")) {
    const std::string where = Where(path, row.line);
    const auto& f = row.fields;
    const auto num = [&](size_t k) { return ParseDouble(f[k], where); };
    switch (format) {
      case TrajectoryFormat::kTum: {
        if (f.size() != 8) throw InputError(where + ": a tum pose has 8 fields, found " + std::to_string(f.size()));
        const Eigen::Quaterniond q(num(7), num(4), num(5), num(6));
        CheckQuaternion(q, where);
        traj.Add(ParseTimestampNs(f[0], 1000000000, where), SE3d(q, {num(1), num(2), num(3)}));
        break;
      }
      case TrajectoryFormat::kEuroc: {
        if (f.size() < 8) throw InputError(where + ": a euroc pose has at least 8 fields, found " + std::to_string(f.size()));
        const Eigen::Quaterniond q(num(4), num(5), num(6), num(7));
        CheckQuaternion(q, where);
        traj.Add(ParseTimestampNs(f[0], 1, where), SE3d(q, {num(1), num(2), num(3)}));
        break;
      }
      case TrajectoryFormat::kKitti: {
        if (f.size() != 12) throw InputError(where + ": a kitti pose has 12 fields, found " + std::to_string(f.size()));
        Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) m(r, c) = num(4 * r + c);
        if (std::abs(m.topLeftCorner<3, 3>().determinant() - 1.0) > 1e-3)
          throw InputError(where + ": the rotation part is not a rotation");
        traj.poses.emplace_back(m);
        break;
      }
    }
  }
  if (traj.empty()) throw InputError(path.string() + ": the trajectory file has no poses");
  return traj;
}

void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string() + ": cannot write file");
  out << "# timestamp tx ty tz qx qy qz qw (world_from_cam)\n";
  char buffer[256];
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const SE3d& pose = trajectory.poses[i];
    const Eigen::Quaterniond& q = pose.So3().Quaternion();
    const Eigen::Vector3d& t = pose.Translation();
    std::snprintf(buffer, sizeof(buffer), " %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t.x(), t.y(), t.z(),
                  q.x(), q.y(), q.z(), q.w());
    out << (trajectory.HasStamps() ? FormatSeconds(trajectory.stamps_ns[i]) : std::to_string(i)) << buffer;
  }
  if (!out) throw InputError(path.string() + ": write failed");
}

}  // namespace dsm
