// SPDX-License-Identifier: MIT
// KITTI odometry: sequences/NN/{image_0/, times.txt, calib.txt}; poses (left camera to world) in
// sequences/NN/poses.txt or poses/NN.txt two levels up.
#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"
#include "dsm/util/parse.h"

namespace dsm {

namespace fs = std::filesystem;

Dataset ReadKitti(const fs::path& root) {
  Dataset d;
  d.format = "kitti";
  d.root = root;
  d.images = MakeFolderStore(root / "image_0");
  d.frames = ReadTimesFile(root / "times.txt", d.images->List(), {0, 1000000000, -1, "timestamp_s"});
  const Image<uint8_t> first = d.images->Load(d.frames.front().image);
  d.camera = ReadKittiCalib(root / "calib.txt", first.width(), first.height());

  fs::path poses = root / "poses.txt";
  if (!fs::exists(poses)) poses = root.parent_path().parent_path() / "poses" / (root.filename().string() + ".txt");
  if (fs::exists(poses)) {
    Trajectory gt = ReadTrajectory(poses, TrajectoryFormat::kKitti);
    if (gt.size() != d.frames.size())
      throw InputError(poses.string() + ": " + std::to_string(gt.size()) + " poses for " +
                       std::to_string(d.frames.size()) + " frames");
    for (const auto& f : d.frames) gt.stamps_ns.push_back(f.t_ns);
    d.ground_truth = std::move(gt);
  }
  return d;
}

}  // namespace dsm
