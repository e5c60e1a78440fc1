// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/bag/bag_dataset.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm::cli {

namespace {

void WriteGroundTruth(const std::string& file, const Trajectory& poses) {
  WriteTumTrajectory(file, poses);
  std::printf("ground truth written to %s\n", file.c_str());
}

}  // namespace

Command AddInfo(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto gt = std::make_shared<GtArgs>();
  auto gt_out = std::make_shared<std::string>();
  auto input = std::make_shared<InputArgs>();
  app.add_option("DATASET", *path,
                 "Dataset folder (EuRoC, TUM monoVO, TUM RGB-D, KITTI or generic), a video file with --calib, or a "
                 "recording (.bag): its topics, then its camera topic as a dataset")
      ->required();
  AddGtOptions(app, gt.get());
  AddInputOptions(app, input.get());
  app.add_option("--gt-out", *gt_out,
                 "Write the ground truth as read (world_from_cam camera poses, after the reading chosen by "
                 "--gt-frame/--gt-quaternion) to this file, TUM format; of a recording without a camera topic, the "
                 "poses of --gt-topic or --gt-frames as they are");
  return [path, gt, gt_out, input] {
    if (IsBagPath(*path)) {
      // A recording: its topics, then its camera topic as a dataset. Without a camera topic (or
      // its calibration), and unless --topic or --calib asked for one, its ground truth alone.
      const std::unique_ptr<BagFile> bag = OpenBagFile(*path);
      std::fputs(DescribeBagTopics(*bag).c_str(), stdout);
      const BagInput bag_input = BagInputFrom(*input, *gt);
      const bool camera_asked = !input->topic.empty() || !input->calib.empty();
      if (!camera_asked && !HasImageTopic(*bag)) {
        std::printf("camera:       none (no sensor_msgs/Image or CompressedImage topic)\n");
        const Trajectory poses = ReadBagGroundTruth(*bag, bag_input);
        if (!poses.empty()) std::printf("ground truth: %zu poses of the tracked body\n", poses.size());
        if (!gt_out->empty()) {
          if (poses.empty()) throw InputError(*path + ": --gt-out needs --gt-topic or --gt-frames");
          WriteGroundTruth(*gt_out, poses);
        }
        return 0;
      }
    }
    const Dataset dataset = OpenInput(*path, *gt, *input);
    std::fputs(DescribeDataset(dataset).c_str(), stdout);
    if (!gt_out->empty()) {
      if (!dataset.HasGroundTruth()) throw InputError(*path + ": the dataset has no ground truth for --gt-out");
      WriteGroundTruth(*gt_out, dataset.ground_truth);
    }
    return 0;
  };
}

}  // namespace dsm::cli
