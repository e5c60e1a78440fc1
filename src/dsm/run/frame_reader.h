// SPDX-License-Identifier: MIT
// Frames as the system takes them: read (decoded), photometrically corrected and undistorted.
//
// FrameReader does this on its own thread (at a lower priority), up to `depth` frames ahead of the
// consumer, as a camera driver fills its buffers while the last frame is processed: decoding and
// undistortion (about half a frame's time at 752x480) overlap tracking instead of adding to it.
// Frames are taken in order. A frame whose file is bad (missing, damaged, another size than the
// calibration's: an InputError) comes with the reason instead of an image, and reading goes on;
// any other error is rethrown when its frame is taken.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "dsm/geometry/undistorter.h"
#include "dsm/image/image.h"
#include "dsm/io/dataset.h"
#include "dsm/system/options.h"

namespace dsm {

// Frame i of `dataset`, ready for System::Process (decoded, photometrically corrected,
// undistorted), or the InputError's message (naming the file) when the frame cannot be used.
struct FrameOrError {
  Image<float> image;
  std::string error;  // Empty: `image` is the frame.
  bool size_mismatch = false;  // The error is an ImageSizeError (the frame decoded, at another size).
  bool damaged = false;        // The error is a DamagedRecordingError (the run stops).
};
FrameOrError TryReadFrame(const Dataset& dataset, const Undistorter& undistorter, int i);
// A frame of `dataset`'s camera ready for System::Process: photometrically corrected, undistorted.
Image<float> PrepareFrame(const Dataset& dataset, const Undistorter& undistorter, const Image<uint8_t>& raw);
// The undistorter of `dataset`'s frames for a System with `options`: the dataset's mode, an output
// size that divides by 2^(pyramid_levels - 1).
Undistorter FrameUndistorter(const Dataset& dataset, const SystemOptions& options);

// The files of the frames after the one being read, asked into memory ahead of it
// (Dataset::PrefetchImage): a recording replayed as a live camera, or read at full speed, does not
// wait for the disk where a file was paged out since it was last read.
class FramePrefetch {
 public:
  static constexpr int kFrames = 10;
  FramePrefetch(const Dataset& dataset, int end) : dataset_(dataset), end_(end) {}
  // Frame i is read now: frames up to i + kFrames are asked for (each once).
  void Reading(int i);

 private:
  const Dataset& dataset_;
  const int end_;
  int next_ = -1;
};

class FrameReader {
 public:
  // Reads frames start .. end-1 (the dataset and undistorter must outlive the reader).
  FrameReader(const Dataset& dataset, const Undistorter& undistorter, int start, int end, int depth);
  ~FrameReader();  // Stops reading and joins.
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  // Frame `index` (the next one in order), once read; rethrows an error other than a bad file.
  FrameOrError Take(int index);

 private:
  void Loop();

  const Dataset& dataset_;
  const Undistorter& undistorter_;
  const int start_, end_, depth_;
  std::mutex mutex_;
  std::condition_variable space_, ready_;
  std::deque<std::pair<int, FrameOrError>> frames_;  // Read, not taken yet, in order.
  std::exception_ptr error_;  // Of the frame after the last one in frames_.
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace dsm
