// SPDX-License-Identifier: MIT
#include "apps/commands.h"
#include "dsm/io/video_dataset.h"
#include "dsm/util/check.h"

namespace dsm::cli {

void AddVideoOptions(CLI::App& app, VideoArgs* args) {
  app.add_option("--calib", args->calib,
                 "Video input: the camera calibration, a camera.yaml (model pinhole | radtan | equidistant | fov; "
                 "see the README's folder format)");
  app.add_option("--groundtruth", args->ground_truth,
                 "Video input: ground-truth camera poses (world_from_cam; TUM, EuRoC or KITTI file) on the "
                 "video's clock");
  app.add_option("--time-offset", args->time_offset_s,
                 "Video input: seconds added to the container's frame times (to match a ground truth's clock)");
}

Dataset OpenInput(const std::string& path, const GtArgs& gt, const VideoArgs& video) {
  if (IsVideoFile(path)) {
    if (!gt.Parse().IsDefault()) throw InputError("--gt-frame / --gt-quaternion apply to EuRoC datasets, not to video");
    return OpenVideo(path, {video.calib, video.ground_truth, video.time_offset_s});
  }
  if (!video.calib.empty() || !video.ground_truth.empty() || video.time_offset_s != 0.0) {
    throw InputError(path + ": --calib, --groundtruth and --time-offset are for video files (mp4, avi, mkv, mov, "
                     "m4v, webm), not for dataset folders");
  }
  return OpenDataset(path, gt.Parse());
}

}  // namespace dsm::cli
