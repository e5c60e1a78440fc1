// SPDX-License-Identifier: MIT
// EuRoC ASL layout. Ground truth is the body (IMU) frame; camera poses are
//   world_from_cam = world_from_body * body_from_cam,   body_from_cam = T_BS of sensor.yaml,
// unless the GroundTruthConvention says the rows are camera poses and/or JPL quaternions.
#include <cstdio>
#include <fstream>

#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

Dataset ReadEuroc(const fs::path& mav0, const GroundTruthConvention& convention) {
  Dataset d;
  d.format = "euroc";
  d.root = mav0.filename() == "mav0" ? mav0.parent_path() : mav0;
  const fs::path cam0 = mav0 / "cam0";
  const EurocSensor sensor = ReadEurocSensorYaml(cam0 / "sensor.yaml");
  d.camera = sensor.camera;
  d.calibration_file = cam0 / "sensor.yaml";

  const fs::path csv = cam0 / "data.csv";
  for (const DataRow& row : ReadDataRows(csv, ",")) {
    if (row.fields.size() != 2) throw InputError(Where(csv, row.line) + ": expected 'timestamp [ns],filename'");
    d.frames.push_back({ParseTimestampNs(row.fields[0], 1, Where(csv, row.line)), std::string(Trim(row.fields[1])), 0.0});
  }
  ValidateFrames(d.frames, csv.string());
  d.images = MakeFolderStore(cam0 / "data");

  const fs::path gt = mav0 / "state_groundtruth_estimate0" / "data.csv";
  if (fs::exists(gt)) {
    const Trajectory rows = ReadTrajectory(gt, TrajectoryFormat::kEuroc);
    for (size_t i = 0; i < rows.size(); ++i) {
      SE3d row = rows.poses[i];
      // JPL: the stored quaternion is the conjugate of the Hamilton one of the same rotation.
      if (convention.quaternion == GtQuaternion::kJpl) row = SE3d(row.So3().Inverse(), row.Translation());
      d.ground_truth.Add(rows.stamps_ns[i], convention.frame == GtFrame::kBody ? row * sensor.body_from_cam : row);
    }
  }
  return d;
}

void WriteEurocGroundTruth(const fs::path& csv, const Trajectory& world_from_cam, const SE3d& body_from_cam,
                           const GroundTruthConvention& gt) {
  DSM_CHECK(world_from_cam.HasStamps(), "EuRoC ground truth needs timestamps");
  std::ofstream out(csv);
  if (!out) throw InputError(csv.string() + ": cannot write file");
  out << "#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n";
  const SE3d cam_from_body = body_from_cam.Inverse();
  char buffer[256];
  for (size_t i = 0; i < world_from_cam.size(); ++i) {
    const SE3d row = gt.frame == GtFrame::kBody ? world_from_cam.poses[i] * cam_from_body : world_from_cam.poses[i];
    Eigen::Quaterniond q = row.So3().Quaternion();
    if (gt.quaternion == GtQuaternion::kJpl) q = q.conjugate();
    const Eigen::Vector3d& p = row.Translation();
    std::snprintf(buffer, sizeof(buffer), ",%.12f,%.12f,%.12f,%.12f,%.12f,%.12f,%.12f\n", p.x(), p.y(), p.z(), q.w(),
                  q.x(), q.y(), q.z());
    out << world_from_cam.stamps_ns[i] << buffer;
  }
  if (!out) throw InputError(csv.string() + ": write failed");
}

}  // namespace dsm
