// SPDX-License-Identifier: MIT
#include "dsm/io/live_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <opencv2/videoio.hpp>

#include "dsm/io/mat_gray.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {


namespace {

constexpr size_t kRecentCaptures = 31;

// FFmpeg reads the start of a stream to learn its format before the first frame, by default
// until it has timed frames enough to estimate their rate (up to 5 s), and then hands the frames
// it read over all at once: a camera's first second in a burst, stamped together. The format is
// known at the first keyframe; the rate is not needed (frames are stamped at capture). A user's
// own OPENCV_FFMPEG_CAPTURE_OPTIONS is kept.
constexpr const char* kCaptureOptions = "fpsprobesize;0|analyzeduration;0";

std::string FrameName(int index) { return "frame " + std::to_string(index); }

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g s", s);
  return text;
}

}  // namespace

std::optional<int> V4l2Index(const std::string& source) {
  std::string digits = source;
  if (source.rfind("/dev/video", 0) == 0) digits = source.substr(10);
  if (digits.empty() || digits.size() > 3 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return std::nullopt;
  return std::stoi(digits);
}

LiveCamera::LiveCamera(const Options& options, Dataset camera) : options_(options), dataset_(std::move(camera)) {
  if (!(options.stall_timeout_s > 0.0) || options.stall_timeout_s > 3600.0)
    throw InputError("--stall-timeout must be within 0 and 3600 seconds");
  dataset_.format = "camera";
  dataset_.root = options.source;
  dataset_.frames.clear();
  const int timeout_ms = static_cast<int>(std::ceil(1000.0 * options.stall_timeout_s));
  capture_ = std::make_unique<cv::VideoCapture>();
  try {
    if (const std::optional<int> index = V4l2Index(options.source)) {
      if (!capture_->open(*index, cv::CAP_V4L2))
        throw InputError(options.source + ": the camera does not open (no V4L2 device /dev/video" +
                         std::to_string(*index) + ", or it is busy)");
    } else if (setenv("OPENCV_FFMPEG_CAPTURE_OPTIONS", kCaptureOptions, /*overwrite=*/0),
               !capture_->open(options.source, cv::CAP_FFMPEG,
                               {cv::CAP_PROP_OPEN_TIMEOUT_MSEC, timeout_ms, cv::CAP_PROP_READ_TIMEOUT_MSEC, timeout_ms})) {
      throw InputError(options.source + ": the stream does not open within " + Seconds(options.stall_timeout_s) +
                       " (nothing sends there, or FFmpeg does not read it)");
    }
  } catch (const cv::Exception& e) {
    throw InputError(options.source + ": the camera does not open (" + e.what() + ")");
  }
  if (!options.record_dir.empty()) recorder_ = std::make_unique<FolderRecorder>(options.record_dir);
  last_capture_ = Clock::now();
  thread_ = std::thread([this] { Loop(); });
}

LiveCamera::~LiveCamera() {
  try {
    Stop();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dsm: %s\n", e.what());
  }
}

void LiveCamera::Loop() {
  Frame end;
  end.status = Status::kEnded;
  const Clock::time_point opened = Clock::now();
  const auto duration = std::chrono::duration<double>(options_.duration_s);
  while (!stop_) {
    if (options_.duration_s > 0.0 && Clock::now() - opened >= duration) {
      end.message = options_.source + ": " + Seconds(options_.duration_s) + " captured (--duration)";
      break;
    }
    cv::Mat mat;
    bool grabbed = false;
    try {
      grabbed = capture_->grab() && capture_->retrieve(mat) && !mat.empty();
    } catch (const cv::Exception&) {
    }
    const Clock::time_point t = Clock::now();
    if (!grabbed) {
      std::lock_guard<std::mutex> lock(mutex_);
      end.message = options_.source + ": the stream ended after " + std::to_string(stamps_ns_.size()) + " frames";
      break;
    }
    Image<uint8_t> image = MatToGray8(mat, options_.source);
    if (image.width() != dataset_.camera.width || image.height() != dataset_.camera.height) {
      end.status = Status::kBadSize;
      end.message = options_.source + ": frames are " + std::to_string(image.width()) + "x" +
                    std::to_string(image.height()) + " but the calibration " + dataset_.calibration_file.string() +
                    " says " + std::to_string(dataset_.camera.width) + "x" + std::to_string(dataset_.camera.height);
      break;
    }
    const int64_t t_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    if (recorder_) recorder_->Add(t_ns, image);
    std::lock_guard<std::mutex> lock(mutex_);
    const int index = static_cast<int>(stamps_ns_.size());
    stamps_ns_.push_back(t_ns);
    newest_ = Frame{Status::kFrame, index, std::move(image), t, ""};
    captured_.push_back(t);
    if (captured_.size() > kRecentCaptures) captured_.erase(captured_.begin());
    last_capture_ = t;
    arrived_.notify_all();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  end_ = std::move(end);
  arrived_.notify_all();
}

LiveCamera::Frame LiveCamera::Take(const std::function<bool()>& give_up) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto stall = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.stall_timeout_s));
  while (!newest_ && !end_) {
    if (give_up && give_up()) return Frame{Status::kEnded, -1, {}, {}, options_.source + ": stopped"};
    const Clock::time_point deadline = last_capture_ + stall;
    if (Clock::now() >= deadline) {
      Frame stalled;
      stalled.status = Status::kStalled;
      stalled.message = options_.source + ": no frame for " + Seconds(options_.stall_timeout_s) +
                        (stamps_ns_.empty() ? " after it opened" : " after frame " + std::to_string(stamps_ns_.size() - 1));
      return stalled;
    }
    arrived_.wait_until(lock, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
  }
  if (!newest_) return *end_;
  Frame frame = std::move(*newest_);
  newest_.reset();
  for (; taken_ <= frame.index; ++taken_) dataset_.frames.push_back({stamps_ns_[taken_], FrameName(taken_), 0.0});
  return frame;
}

std::optional<LiveCamera::Clock::time_point> LiveCamera::Expected(int index) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (captured_.size() < 2) return std::nullopt;
  std::vector<double> intervals;
  for (size_t k = 1; k < captured_.size(); ++k)
    intervals.push_back(std::chrono::duration<double>(captured_[k] - captured_[k - 1]).count());
  const int last = static_cast<int>(stamps_ns_.size()) - 1;
  const double ahead_s = Median(intervals) * (index - last);
  return captured_.back() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(ahead_s));
}

int LiveCamera::captured() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(stamps_ns_.size());
}

void LiveCamera::Stop() {
  if (stopped_) return;
  stopped_ = true;
  stop_ = true;
  // The capture thread ends at its next grab: the next frame, the end of the stream or the read
  // timeout (the stall timeout).
  if (thread_.joinable()) thread_.join();
  capture_->release();
  if (!recorder_) return;
  CameraYaml yaml;
  yaml.camera = dataset_.camera;
  if (dataset_.line_delay_source != LineDelaySource::kUnknown) yaml.line_delay_us = dataset_.line_delay_us;
  recorder_->Close(yaml);
}

}  // namespace dsm
