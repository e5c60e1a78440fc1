// SPDX-License-Identifier: MIT
#include "dsm/io/euroc_copy.h"

#include <algorithm>
#include <fstream>

#include "dsm/io/calibration_io.h"
#include "dsm/io/image_io.h"
#include "dsm/image/defects.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

void WriteEurocCopy(const fs::path& src, const fs::path& dst, size_t frames, const GroundTruthConvention& reading,
                    const std::string& defects) {
  const Dataset d = OpenDataset(src);
  if (d.format != "euroc") throw InputError(src.string() + ": not a EuRoC folder (" + d.format + ")");
  const fs::path cam0 = dst / "mav0" / "cam0";
  fs::create_directories(cam0);
  fs::copy_file(src / "mav0" / "cam0" / "sensor.yaml", cam0 / "sensor.yaml", fs::copy_options::overwrite_existing);
  const fs::path data = fs::absolute(src / "mav0" / "cam0" / "data");
  const std::vector<Defect> spoiled = ParseDefects(defects);
  const auto cut = [&](size_t i) { return IsCut(spoiled, static_cast<int>(i)); };
  if (spoiled.empty()) {
    fs::create_directory_symlink(data, cam0 / "data");
  } else {
    // Every image linked but the spoiled ones (a damaged file is a copy, never the original).
    fs::create_directories(cam0 / "data");
    for (size_t i = 0; i < std::min(frames, d.size()); ++i) {
      if (cut(i)) continue;
      const fs::path to = cam0 / "data" / d.frames[i].image;
      const auto hit = [&](bool file) { return FindDefect(spoiled, static_cast<int>(i), file) != nullptr; };
      if (hit(false)) {
        Image<uint8_t> image = d.LoadImage(i);
        ApplyImageDefects(spoiled, static_cast<int>(i), 1, &image);
        WriteGray8(to, image);
      } else if (hit(true)) {
        fs::copy_file(data / d.frames[i].image, to);
        ApplyFileDefects(spoiled, static_cast<int>(i), to);
      } else {
        fs::create_symlink(data / d.frames[i].image, to);
      }
    }
  }
  std::ofstream csv(cam0 / "data.csv");
  csv << "#timestamp [ns],filename\n";
  for (size_t i = 0; i < std::min(frames, d.size()); ++i)
    if (!cut(i)) csv << d.frames[i].t_ns << "," << d.frames[i].image << "\n";
  DSM_CHECK(csv.good(), "cannot write " + (cam0 / "data.csv").string());
  if (!d.HasGroundTruth()) return;
  fs::create_directories(dst / "mav0" / "state_groundtruth_estimate0");
  const SE3d body_from_cam = ReadEurocSensorYaml(cam0 / "sensor.yaml").body_from_cam;
  WriteEurocGroundTruth(dst / "mav0" / "state_groundtruth_estimate0" / "data.csv", d.ground_truth, body_from_cam,
                        reading);
}

}  // namespace dsm
