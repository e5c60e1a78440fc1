// SPDX-License-Identifier: MIT
// Trajectory files (`dsm eval`, ground truth): the first byte picks tum, euroc, kitti or
// detection from the first line (as `dsm eval` does without --format).
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dsm::fuzz::Choice choice = dsm::fuzz::Split(data, size, 4);
  const std::filesystem::path path = dsm::fuzz::Scratch() / "trajectory.txt";
  dsm::fuzz::WriteFile(path, choice.text);
  try {
    const dsm::TrajectoryFormat format =
        choice.file < 3 ? static_cast<dsm::TrajectoryFormat>(choice.file) : dsm::DetectTrajectoryFormat(path);
    const dsm::Trajectory trajectory = dsm::ReadTrajectory(path, format);
    dsm::fuzz::CheckTrajectory(trajectory);
    DSM_CHECK(trajectory.HasStamps() == (format != dsm::TrajectoryFormat::kKitti), "stamps where none belong");
    dsm::fuzz::Report("accepted");
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
  }
  return 0;
}
