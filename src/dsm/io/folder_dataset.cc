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
  d.camera = cam.camera;
  d.images = MakeFolderStore(root / "images");
  const auto names = d.images->List();
  if (names.empty()) throw InputError((root / "images").string() + ": no images");
  const fs::path times = root / "times.txt";
  if (fs::exists(times)) {
    const auto lines = ReadLines(times);
    for (size_t i = 0; i < lines.size(); ++i) {
      const std::string_view line = Trim(lines[i]);
      if (line.empty() || line.front() == '#') continue;
      const auto f = SplitFields(line, " \t,");
      const std::string where = Where(times, i);
      if (f.size() > 2) throw InputError(where + ": expected 'timestamp_ns [exposure_ms]'");
      const size_t k = d.frames.size();
      if (k >= names.size()) throw InputError(where + ": more timestamps than images");
      const double exposure = f.size() == 2 ? ParseDouble(f[1], where) : 0.0;
      if (exposure < 0) throw InputError(where + ": negative exposure time");
      d.frames.push_back({ParseTimestampNs(f[0], 1, where), names[k], exposure});
    }
    if (d.frames.size() != names.size())
      throw InputError(times.string() + ": " + std::to_string(d.frames.size()) + " timestamps for " +
                       std::to_string(names.size()) + " images");
  } else {
    for (size_t i = 0; i < names.size(); ++i)
      d.frames.push_back({static_cast<int64_t>(std::llround(i * 1e9 / cam.rate_hz)), names[i], 0.0});
  }
  ValidateFrames(d.frames, times.string());
  if (fs::exists(root / "groundtruth.tum")) d.ground_truth = ReadTrajectory(root / "groundtruth.tum", TrajectoryFormat::kTum);
  d.photometric = ReadPhotometricCalibration(root);
  return d;
}

}  // namespace dsm
