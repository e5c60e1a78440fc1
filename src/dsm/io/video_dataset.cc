// SPDX-License-Identifier: MIT
#include "dsm/io/video_dataset.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <mutex>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>

#include "dsm/io/calibration_io.h"
#include "dsm/io/mat_gray.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

std::string FrameName(size_t index) { return "frame " + std::to_string(index); }

// OpenCV's FFmpeg backend; its own warnings silenced (our errors name the file instead).
cv::VideoCapture OpenCapture(const fs::path& video) {
  static std::once_flag quiet;
  std::call_once(quiet, [] {
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    // FFmpeg's own messages ("moov atom not found"): OpenCV's backend reads this when it first
    // starts FFmpeg; -8 is AV_LOG_QUIET. A value the user set is kept.
    setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", /*overwrite=*/0);
  });
  std::error_code ec;
  if (!fs::is_regular_file(video, ec)) throw InputError(video.string() + ": no such video file");
  cv::VideoCapture capture;
  try {
    capture.open(video.string(), cv::CAP_FFMPEG);
  } catch (const cv::Exception&) {
  }
  if (!capture.isOpened()) throw InputError(video.string() + ": cannot open as a video (not a video file, or damaged)");
  return capture;
}

// Frames decoded in order; a frame before the last one decoded reopens the video.
class VideoStore : public ImageStore {
 public:
  VideoStore(fs::path video, size_t frames) : video_(std::move(video)), frames_(frames) {}

  Image<uint8_t> Load(const std::string& name) const override {
    size_t index = 0;
    if (name.rfind("frame ", 0) != 0 || !ParseIndex(name.substr(6), &index) || index >= frames_) {
      throw InputError(video_.string() + ": no " + name);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (!capture_.isOpened() || index < next_) {
      capture_ = OpenCapture(video_);
      next_ = 0;
    }
    cv::Mat frame;
    bool ok = true;
    try {
      for (; ok && next_ < index; ++next_) ok = capture_.grab();
      ok = ok && capture_.read(frame) && !frame.empty();
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) {
      capture_.release();
      throw InputError(video_.string() + ": cannot decode " + name);
    }
    next_ = index + 1;
    return MatToGray8(frame, video_.string() + " " + name);
  }

  std::vector<std::string> List() const override {
    std::vector<std::string> names;
    for (size_t i = 0; i < frames_; ++i) names.push_back(FrameName(i));
    return names;
  }

  std::string Describe() const override { return video_.string() + " (video, " + std::to_string(frames_) + " frames)"; }

 private:
  static bool ParseIndex(const std::string& text, size_t* index) {
    if (text.empty() || !std::all_of(text.begin(), text.end(), [](char c) { return std::isdigit(c) != 0; })) return false;
    *index = std::stoull(text);
    return true;
  }
  fs::path video_;
  size_t frames_;
  mutable std::mutex mutex_;
  mutable cv::VideoCapture capture_;
  mutable size_t next_ = 0;  // Index of the frame the capture reads next.
};

}  // namespace

bool IsVideoFile(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".mp4" || ext == ".avi" || ext == ".mkv" || ext == ".mov" || ext == ".m4v" || ext == ".webm";
}

std::shared_ptr<ImageStore> OpenVideoFrames(const fs::path& video) {
  cv::VideoCapture capture = OpenCapture(video);
  size_t frames = 0;
  try {
    while (capture.grab()) ++frames;
  } catch (const cv::Exception&) {
  }
  if (frames == 0) throw InputError(video.string() + ": no frame could be decoded");
  return std::make_shared<VideoStore>(video, frames);
}

Dataset OpenVideo(const fs::path& video, const VideoInput& input) {
  if (input.camera_yaml.empty()) {
    throw InputError(video.string() + ": a video needs its camera calibration (--calib CAMERA.yaml)");
  }
  if (!(std::abs(input.time_offset_s) < 9e9)) throw InputError("--time-offset must be a number of seconds below 9e9");
  Dataset d;
  d.format = "video";
  d.root = video;
  const CameraYaml yaml = ReadCameraYaml(input.camera_yaml);
  d.camera = yaml.camera;
  d.calibration_file = input.camera_yaml;
  if (yaml.line_delay_us) {
    d.line_delay_us = *yaml.line_delay_us;
    d.line_delay_source = LineDelaySource::kCalibration;
  }

  // One pass over the video: the frame count and each frame's presentation time.
  cv::VideoCapture capture = OpenCapture(video);
  const int width = static_cast<int>(capture.get(cv::CAP_PROP_FRAME_WIDTH));
  const int height = static_cast<int>(capture.get(cv::CAP_PROP_FRAME_HEIGHT));
  if (width != d.camera.width || height != d.camera.height) {
    throw InputError(video.string() + ": frames are " + std::to_string(width) + "x" + std::to_string(height) + " but " +
                     input.camera_yaml.string() + " says " + std::to_string(d.camera.width) + "x" +
                     std::to_string(d.camera.height));
  }
  const double fps = capture.get(cv::CAP_PROP_FPS);
  std::vector<double> ms;
  try {
    while (capture.grab()) ms.push_back(capture.get(cv::CAP_PROP_POS_MSEC));
  } catch (const cv::Exception&) {
  }
  if (ms.empty()) throw InputError(video.string() + ": no frame could be decoded");
  // Presentation times that do not increase (a container without them): frame index over the rate.
  bool increasing = true;
  for (size_t i = 1; i < ms.size(); ++i) increasing = increasing && ms[i] > ms[i - 1];
  if (!increasing) {
    if (!(fps > 0.0)) throw InputError(video.string() + ": neither frame times nor a frame rate in the container");
    for (size_t i = 0; i < ms.size(); ++i) ms[i] = 1000.0 * i / fps;
  }
  const int64_t offset_ns = std::llround(1e9 * input.time_offset_s);
  for (size_t i = 0; i < ms.size(); ++i) d.frames.push_back({std::llround(1e6 * ms[i]) + offset_ns, FrameName(i), 0.0});
  ValidateFrames(d.frames, video.string());
  d.images = std::make_shared<VideoStore>(video, ms.size());
  if (!input.ground_truth.empty()) {
    d.ground_truth = ReadTrajectory(input.ground_truth, DetectTrajectoryFormat(input.ground_truth));
  }
  return d;
}

}  // namespace dsm
