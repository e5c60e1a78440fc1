// SPDX-License-Identifier: MIT
// TUM monoVO and TUM RGB-D layouts.
#include <map>

#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

Dataset ReadTumMono(const fs::path& root) {
  Dataset d;
  d.format = "tum-mono";
  d.root = root;
  const TumMonoCamera cam = ReadTumMonoCamera(root / "camera.txt");
  d.camera = cam.camera;
  d.calibration_file = root / "camera.txt";
  d.undistort_mode = cam.mode;
  if (fs::is_directory(root / "images")) {
    d.images = MakeFolderStore(root / "images");
  } else if (fs::exists(root / "images.zip")) {
    d.images = MakeZipStore(root / "images.zip");
  } else {
    throw InputError(root.string() + ": neither images/ nor images.zip found");
  }
  // times.txt: "id timestamp_s [exposure_ms]", one row per image in name order.
  d.frames = ReadTimesFile(root / "times.txt", d.images->List(), {1, 1000000000, 2, "id timestamp_s [exposure_ms]"});
  d.photometric = ReadPhotometricCalibration(root);
  return d;
}

namespace {

// Published intrinsics of the TUM RGB-D Freiburg cameras (colour camera, radtan k1 k2 p1 p2 k3).
std::optional<CameraCalibration> FreiburgCamera(const std::string& folder_name) {
  CameraCalibration c;
  c.model = CameraModel::kRadTan;
  c.width = 640;
  c.height = 480;
  if (folder_name.find("freiburg1") != std::string::npos) {
    c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
    c.distortion = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  } else if (folder_name.find("freiburg2") != std::string::npos) {
    c.fx = 520.9, c.fy = 521.0, c.cx = 325.1, c.cy = 249.7;
    c.distortion = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  } else if (folder_name.find("freiburg3") != std::string::npos) {
    c.model = CameraModel::kPinhole;
    c.fx = 535.4, c.fy = 539.2, c.cx = 320.1, c.cy = 247.6;
  } else {
    return std::nullopt;
  }
  return c;
}

}  // namespace

Dataset ReadTumRgbd(const fs::path& root) {
  Dataset d;
  d.format = "tum-rgbd";
  d.root = root;
  if (fs::exists(root / "camera.yaml")) {
    d.camera = ReadCameraYaml(root / "camera.yaml").camera;
    d.calibration_file = root / "camera.yaml";
  } else if (auto cam = FreiburgCamera(fs::absolute(root).lexically_normal().filename().string())) {
    d.camera = *cam;
  } else {
    throw InputError(root.string() + ": no calibration: add a camera.yaml (as in the folder format) to this TUM RGB-D folder");
  }
  d.images = MakeFolderStore(root);
  const fs::path rgb = root / "rgb.txt";
  for (const DataRow& row : ReadDataRows(rgb)) {
    if (row.fields.size() != 2) throw InputError(Where(rgb, row.line) + ": expected 'timestamp filename'");
    d.frames.push_back({ParseTimestampNs(row.fields[0], 1000000000, Where(rgb, row.line)), row.fields[1], 0.0});
  }
  ValidateFrames(d.frames, rgb.string());
  if (fs::exists(root / "groundtruth.txt")) d.ground_truth = ReadTrajectory(root / "groundtruth.txt", TrajectoryFormat::kTum);
  return d;
}

}  // namespace dsm
