// SPDX-License-Identifier: MIT
#include "dsm/io/folder_dataset.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

std::string FolderImageName(size_t i) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu.png", i);
  return name;
}

void WriteFolderTimes(const fs::path& root, const std::vector<FrameRecord>& frames) {
  std::ofstream out(root / "times.txt");
  if (!out) throw InputError((root / "times.txt").string() + ": cannot write file");
  out << "# timestamp_ns exposure_ms (one row per image, in name order)\n";
  char buffer[64];
  for (const auto& f : frames) {
    std::snprintf(buffer, sizeof(buffer), " %.6f\n", f.exposure_ms);
    out << f.t_ns << buffer;
  }
  if (!out) throw InputError((root / "times.txt").string() + ": write failed");
}

Dataset ReadFolder(const fs::path& root) {
  Dataset d;
  d.format = "folder";
  d.root = root;
  const CameraYaml cam = ReadCameraYaml(root / "camera.yaml");
  if (cam.line_delay_us) {
    d.line_delay_us = *cam.line_delay_us;
    d.line_delay_source = LineDelaySource::kCalibration;
  }
  d.camera = cam.camera;
  d.calibration_file = root / "camera.yaml";
  d.images = MakeFolderStore(root / "images");
  const auto names = d.images->List();
  if (names.empty()) throw InputError((root / "images").string() + ": no images");
  const fs::path times = root / "times.txt";
  if (fs::exists(times)) {
    d.frames = ReadTimesFile(times, names, {0, 1, 1, "timestamp_ns [exposure_ms]"});
  } else {
    for (size_t i = 0; i < names.size(); ++i)
      d.frames.push_back({static_cast<int64_t>(std::llround(i * 1e9 / cam.rate_hz)), names[i], 0.0});
  }
  if (fs::exists(root / "groundtruth.tum")) d.ground_truth = ReadTrajectory(root / "groundtruth.tum", TrajectoryFormat::kTum);
  d.photometric = ReadPhotometricCalibration(root);
  if (fs::is_directory(root / "depth")) d.depth_dir = root / "depth";
  return d;
}

}  // namespace dsm
