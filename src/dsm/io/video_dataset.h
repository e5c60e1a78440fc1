// SPDX-License-Identifier: MIT
// A video file as a dataset (OpenCV videoio with its FFmpeg backend): mp4, avi, mkv, mov, m4v,
// webm. The camera comes from a `camera.yaml` (calibration_io.h: pinhole, radtan, equidistant or
// fov); the frames' timestamps from the container (each frame's presentation time, plus an
// optional offset onto another clock); optional ground truth from a trajectory file
// (world_from_cam camera poses, TUM / EuRoC / KITTI detected, on the same clock).
//
// The video is read through once when it is opened, to count its frames and take their times (a
// container's frame count and rate are not always right); frames are then decoded in order as the
// run takes them.
#pragma once

#include <filesystem>
#include <memory>

#include "dsm/io/dataset.h"
#include "dsm/io/image_store.h"

namespace dsm {

struct VideoInput {
  std::filesystem::path camera_yaml;    // Required.
  std::filesystem::path ground_truth;   // Optional.
  double time_offset_s = 0.0;           // Added to the container's timestamps.
};

// True for the file name endings read as video (case-insensitive).
bool IsVideoFile(const std::filesystem::path& path);

// The frames of `video` as images ("frame 0", "frame 1", ...), without a calibration: read through
// once to count them, then decoded in order as they are loaded. Throws InputError naming the file
// when it cannot be opened or holds no frame.
std::shared_ptr<ImageStore> OpenVideoFrames(const std::filesystem::path& video);

// Throws InputError naming the file when the video cannot be opened or decoded, holds fewer than
// one frame, or differs in size from the calibration; and for a bad camera.yaml or ground truth.
Dataset OpenVideo(const std::filesystem::path& video, const VideoInput& input);

}  // namespace dsm
