// SPDX-License-Identifier: MIT
#include "dsm/io/euroc_copy.h"

#include <fstream>

#include "dsm/io/calibration_io.h"
#include "dsm/util/check.h"

namespace dsm::testing {

namespace fs = std::filesystem;

void WriteEurocCopy(const fs::path& src, const fs::path& dst, size_t frames, const GroundTruthConvention& reading) {
  const Dataset d = OpenDataset(src);
  DSM_CHECK(d.format == "euroc" && d.HasGroundTruth(), src.string() + " is no EuRoC dataset with ground truth");
  const fs::path cam0 = dst / "mav0" / "cam0";
  fs::create_directories(cam0);
  fs::create_directories(dst / "mav0" / "state_groundtruth_estimate0");
  fs::copy_file(src / "mav0" / "cam0" / "sensor.yaml", cam0 / "sensor.yaml", fs::copy_options::overwrite_existing);
  fs::create_directory_symlink(fs::absolute(src / "mav0" / "cam0" / "data"), cam0 / "data");
  std::ofstream csv(cam0 / "data.csv");
  csv << "#timestamp [ns],filename\n";
  for (size_t i = 0; i < std::min(frames, d.size()); ++i) csv << d.frames[i].t_ns << "," << d.frames[i].image << "\n";
  DSM_CHECK(csv.good(), "cannot write " + (cam0 / "data.csv").string());
  const SE3d body_from_cam = ReadEurocSensorYaml(cam0 / "sensor.yaml").body_from_cam;
  WriteEurocGroundTruth(dst / "mav0" / "state_groundtruth_estimate0" / "data.csv", d.ground_truth, body_from_cam,
                        reading);
}

}  // namespace dsm::testing
