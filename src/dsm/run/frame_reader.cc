// SPDX-License-Identifier: MIT
#include "dsm/run/frame_reader.h"

#include <algorithm>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "dsm/util/check.h"

namespace dsm {

Undistorter FrameUndistorter(const Dataset& dataset, const SystemOptions& options) {
  return Undistorter(dataset.camera, {dataset.undistort_mode, 1 << (options.pyramid_levels - 1)});
}

Image<float> PrepareFrame(const Dataset& dataset, const Undistorter& undistorter, const Image<uint8_t>& raw) {
  return dataset.photometric ? undistorter.Apply(dataset.photometric->ToIrradiance(raw)) : undistorter.Apply(raw);
}

FrameOrError TryReadFrame(const Dataset& dataset, const Undistorter& undistorter, int i) {
  FrameOrError out;
  try {
    out.image = PrepareFrame(dataset, undistorter, dataset.LoadImage(i));
  } catch (const ImageSizeError& e) {
    out.error = e.what();
    out.size_mismatch = true;
  } catch (const DamagedRecordingError& e) {
    out.error = e.what();
    out.damaged = true;
  } catch (const InputError& e) {
    out.error = e.what();
  }
  return out;
}

FrameReader::FrameReader(const Dataset& dataset, const Undistorter& undistorter, int start, int end, int depth)
    : dataset_(dataset), undistorter_(undistorter), start_(start), end_(end), depth_(depth) {
  DSM_CHECK(depth >= 1, "the reader needs a buffer");
  thread_ = std::thread([this] { Loop(); });
}

FrameReader::~FrameReader() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  thread_.join();
}

void FramePrefetch::Reading(int i) {
  next_ = std::max(next_, i + 1);
  for (; next_ < std::min(end_, i + kFrames + 1); ++next_) dataset_.PrefetchImage(next_);
}

void FrameReader::Loop() {
  // Below the tracking and mapping threads (nice 10, this thread only): reading fills their idle
  // time instead of taking a core from them. Best effort: a failure leaves the default priority.
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
  FramePrefetch prefetch(dataset_, end_);
  for (int i = start_; i < end_; ++i) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return stop_ || static_cast<int>(frames_.size()) < depth_; });
      if (stop_) return;
    }
    bool failed = false;
    prefetch.Reading(i);
    try {
      FrameOrError frame = TryReadFrame(dataset_, undistorter_, i);
      std::lock_guard<std::mutex> lock(mutex_);
      frames_.emplace_back(i, std::move(frame));
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
      failed = true;
    }
    ready_.notify_one();
    if (failed) return;
  }
}

FrameOrError FrameReader::Take(int index) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return !frames_.empty() || error_ != nullptr; });
  if (frames_.empty()) std::rethrow_exception(error_);
  DSM_CHECK(frames_.front().first == index, "frames are taken in order");
  FrameOrError frame = std::move(frames_.front().second);
  frames_.pop_front();
  lock.unlock();
  space_.notify_one();
  return frame;
}

}  // namespace dsm
