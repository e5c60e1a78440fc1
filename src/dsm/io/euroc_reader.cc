// SPDX-License-Identifier: MIT
// EuRoC ASL layout. Ground truth is the body (IMU) frame; camera poses are
//   world_from_cam = world_from_body * body_from_cam,   body_from_cam = T_BS of sensor.yaml,
// unless the GroundTruthConvention says the rows are camera poses and/or JPL quaternions.
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

}  // namespace dsm
