// SPDX-License-Identifier: MIT
// A live camera as a run's input: a V4L2 device (/dev/videoN, or its index N) or a stream URL
// (rtsp://, http://, tcp://, udp://, ... through OpenCV's FFmpeg back-end), read on a capture
// thread of its own.
//
// Each frame is stamped when its grab returns, on the monotonic clock (steady_clock), and kept in
// a one-frame mailbox as a camera driver keeps the newest frame: a frame not taken before the next
// one comes is dropped. Take() hands the newest frame over and appends the records of every frame
// captured up to it (dropped ones included, named "frame N") to dataset().frames, so a frame's
// index is its capture number. With a recording folder, every frame captured is also written
// there as a folder dataset (images/, times.txt, camera.yaml) that dsm run replays.
//
// The run ends with the stream (its end, or a device gone), with no frame for the stall timeout,
// or with a frame whose size is not the calibration's: Take() says which, with a message naming
// the source.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dsm/image/image.h"
#include "dsm/io/dataset.h"
#include "dsm/io/folder_recorder.h"

namespace cv {
class VideoCapture;
}

namespace dsm {

class LiveCamera {
 public:
  using Clock = std::chrono::steady_clock;

  struct Options {
    std::string source;                // /dev/videoN, N, or a URL.
    double stall_timeout_s = 5.0;      // No frame for this long ends the run (the first: opening fails).
    std::filesystem::path record_dir;  // Non-empty: every frame captured is written there.
    double duration_s = 0.0;           // > 0: the stream ends after this long.
  };

  enum class Status {
    kFrame,    // A frame.
    kEnded,    // The stream ended (or the device stopped delivering, or the duration passed).
    kStalled,  // No frame for the stall timeout.
    kBadSize,  // A frame of another size than the calibration's.
  };
  struct Frame {
    Status status = Status::kEnded;
    int index = -1;             // Its capture number (kFrame).
    Image<uint8_t> image;       // 8-bit grey (kFrame).
    Clock::time_point captured;  // When its grab returned (kFrame).
    std::string message;        // Otherwise: what happened, naming the source.
  };

  // Opens the source and starts capturing. `camera` is the dataset the frames join: its format,
  // root and frames are set here, its calibration is the caller's (a camera.yaml). Throws
  // InputError naming the source when it does not open, or sends no frame within the stall
  // timeout.
  LiveCamera(const Options& options, Dataset camera);
  ~LiveCamera();  // Stops capturing (Stop).
  LiveCamera(const LiveCamera&) = delete;
  LiveCamera& operator=(const LiveCamera&) = delete;

  // The newest frame after the last one taken; blocks until there is one, the stream ends, the
  // stall timeout passes without a frame, or `give_up` (asked every 100 ms) says so (kEnded).
  // Call from one thread; dataset() is that thread's.
  Frame Take(const std::function<bool()>& give_up = nullptr);
  // When capture `index` (after the last one taken) is expected: the last capture plus the median
  // interval of the recent ones (none before two frames).
  std::optional<Clock::time_point> Expected(int index) const;
  const Dataset& dataset() const { return dataset_; }
  int captured() const;  // Frames captured so far.
  // Stops capturing and finishes the recording (its times.txt and camera.yaml); idempotent.
  void Stop();

 private:
  void Loop();

  const Options options_;
  Dataset dataset_;
  std::unique_ptr<cv::VideoCapture> capture_;
  std::unique_ptr<FolderRecorder> recorder_;  // With a recording folder.
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  // Shared with the capture thread, under mutex_.
  std::optional<Frame> newest_;
  std::vector<int64_t> stamps_ns_;          // Of every frame captured.
  std::vector<Clock::time_point> captured_;  // The recent captures (Expected).
  Clock::time_point last_capture_;
  std::optional<Frame> end_;  // How the stream ended.
  std::atomic<bool> stop_{false};
  bool stopped_ = false;
  int taken_ = 0;  // Records appended to dataset_.frames (the caller's thread).
  std::thread thread_;
};

// The index N of a V4L2 device given as /dev/videoN or N; none for a URL.
std::optional<int> V4l2Index(const std::string& source);

}  // namespace dsm
