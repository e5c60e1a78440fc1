// SPDX-License-Identifier: MIT
// A folder dataset (folder_dataset.h) written as frames come, on a thread of its own so that the
// one who hands frames over never waits for the disk: images/NNNNNN.png as added, times.txt and
// camera.yaml when closed. Frames are numbered from 0 in the order added; the queue of frames not
// yet written is unbounded (a disk slower than the camera costs memory, not frames).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "dsm/image/image.h"
#include "dsm/io/calibration_io.h"

namespace dsm {

class FolderRecorder {
 public:
  // Creates `dir`/images (InputError naming it when it cannot).
  explicit FolderRecorder(std::filesystem::path dir);
  ~FolderRecorder();  // Close(), its errors on stderr.
  FolderRecorder(const FolderRecorder&) = delete;
  FolderRecorder& operator=(const FolderRecorder&) = delete;

  void Add(int64_t t_ns, Image<uint8_t> image);
  // Writes the frames still queued, then times.txt and `camera` as camera.yaml (its rate_hz from
  // the frames' times); throws InputError naming the file that could not be written. Idempotent.
  void Close(CameraYaml camera);

 private:
  void Loop();

  const std::filesystem::path dir_;
  std::mutex mutex_;
  std::condition_variable queued_;
  std::deque<std::pair<int, Image<uint8_t>>> queue_;
  std::vector<int64_t> stamps_ns_;
  std::string error_;  // The first image that could not be written.
  bool closing_ = false, closed_ = false;
  std::thread thread_;
};

}  // namespace dsm
