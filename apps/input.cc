// SPDX-License-Identifier: MIT
#include "apps/commands.h"
#include "dsm/bag/bag_dataset.h"
#include "dsm/io/video_dataset.h"
#include "dsm/util/check.h"

namespace dsm::cli {

void AddInputOptions(CLI::App& app, InputArgs* args) {
  app.add_option("--calib", args->calib,
                 "Video or recording input: the camera calibration, a camera.yaml (model pinhole | radtan | "
                 "equidistant | fov; see the README's folder format); for a recording also EuRoC's sensor.yaml "
                 "(its T_BS places the camera on the body --gt-topic tracks), or none: the recording's CameraInfo");
  app.add_option("--groundtruth", args->ground_truth,
                 "Video input: ground-truth camera poses (world_from_cam; TUM, EuRoC or KITTI file) on the "
                 "video's clock");
  app.add_option("--time-offset", args->time_offset_s,
                 "Video input: seconds added to the container's frame times (to match a ground truth's clock)");
  app.add_option("--topic", args->topic,
                 "Recording input: the image topic (sensor_msgs/Image or CompressedImage); default: the only one");
  app.add_option("--gt-topic", args->gt_topic,
                 "Recording input: ground truth from this topic's poses (PoseStamped, PoseWithCovarianceStamped, "
                 "TransformStamped, Odometry): the tracked body's, turned into the camera's by T_BS when --calib is "
                 "EuRoC's sensor.yaml");
  app.add_option("--gt-frames", args->gt_frames,
                 "Recording input: ground truth from the transforms PARENT -> CHILD on /tf and /tf_static")
      ->expected(2);
}

BagInput BagInputFrom(const InputArgs& args, const GtArgs& gt) {
  BagInput input;
  input.topic = args.topic;
  input.calib = args.calib;
  input.gt_topic = args.gt_topic;
  if (args.gt_frames.size() == 2) input.gt_parent = args.gt_frames[0], input.gt_child = args.gt_frames[1];
  input.gt = gt.Parse();
  return input;
}

Dataset OpenInput(const std::string& path, const GtArgs& gt, const InputArgs& args) {
  const bool bag_options = !args.topic.empty() || !args.gt_topic.empty() || !args.gt_frames.empty();
  if (IsBagPath(path)) {
    if (!args.ground_truth.empty() || args.time_offset_s != 0.0) {
      throw InputError(path + ": --groundtruth and --time-offset are for video files; a recording's ground truth "
                       "comes from --gt-topic or --gt-frames");
    }
    return OpenBag(path, BagInputFrom(args, gt));
  }
  if (bag_options) throw InputError(path + ": --topic, --gt-topic and --gt-frames are for recordings (.bag)");
  if (IsVideoFile(path)) {
    if (!gt.Parse().IsDefault()) throw InputError("--gt-frame / --gt-quaternion apply to EuRoC datasets, not to video");
    return OpenVideo(path, {args.calib, args.ground_truth, args.time_offset_s});
  }
  if (!args.calib.empty() || !args.ground_truth.empty() || args.time_offset_s != 0.0) {
    throw InputError(path + ": --calib, --groundtruth and --time-offset are for video files (mp4, avi, mkv, mov, "
                     "m4v, webm), not for dataset folders");
  }
  return OpenDataset(path, gt.Parse());
}

}  // namespace dsm::cli
