// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm::cli {

Command AddInfo(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto gt = std::make_shared<GtArgs>();
  auto gt_out = std::make_shared<std::string>();
  auto video = std::make_shared<VideoArgs>();
  app.add_option("DATASET", *path, "Dataset folder (EuRoC, TUM monoVO, TUM RGB-D, KITTI or generic), or a video file with --calib")
      ->required();
  AddGtOptions(app, gt.get());
  AddVideoOptions(app, video.get());
  app.add_option("--gt-out", *gt_out,
                 "Write the ground truth as read (world_from_cam camera poses, after the reading chosen by "
                 "--gt-frame/--gt-quaternion) to this file, TUM format");
  return [path, gt, gt_out, video] {
    const Dataset dataset = OpenInput(*path, *gt, *video);
    std::fputs(DescribeDataset(dataset).c_str(), stdout);
    if (!gt_out->empty()) {
      if (!dataset.HasGroundTruth()) throw InputError(*path + ": the dataset has no ground truth for --gt-out");
      WriteTumTrajectory(*gt_out, dataset.ground_truth);
      std::printf("ground truth written to %s\n", gt_out->c_str());
    }
    return 0;
  };
}

}  // namespace dsm::cli
