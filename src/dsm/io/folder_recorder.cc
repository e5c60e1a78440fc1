// SPDX-License-Identifier: MIT
#include "dsm/io/folder_recorder.h"

#include <cstdio>

#include "dsm/io/dataset.h"
#include "dsm/io/folder_dataset.h"
#include "dsm/io/image_io.h"
#include "dsm/util/check.h"

namespace dsm {

namespace fs = std::filesystem;

FolderRecorder::FolderRecorder(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_ / "images", ec);
  if (ec) throw InputError(dir_.string() + ": cannot create the recording folder (" + ec.message() + ")");
  thread_ = std::thread([this] { Loop(); });
}

FolderRecorder::~FolderRecorder() {
  try {
    Close(CameraYaml{});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dsm: %s\n", e.what());
  }
}

void FolderRecorder::Add(int64_t t_ns, Image<uint8_t> image) {
  std::lock_guard<std::mutex> lock(mutex_);
  queue_.emplace_back(static_cast<int>(stamps_ns_.size()), std::move(image));
  stamps_ns_.push_back(t_ns);
  queued_.notify_one();
}

void FolderRecorder::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    queued_.wait(lock, [this] { return closing_ || !queue_.empty(); });
    if (queue_.empty()) return;  // Closing, all written.
    std::pair<int, Image<uint8_t>> frame = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    try {
      WriteGray8(dir_ / "images" / FolderImageName(frame.first), frame.second);
    } catch (const InputError& e) {
      lock.lock();
      if (error_.empty()) error_ = e.what();
      continue;
    }
    lock.lock();
  }
}

void FolderRecorder::Close(CameraYaml camera) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return;
    closed_ = closing_ = true;
    queued_.notify_one();
  }
  thread_.join();
  if (!error_.empty()) throw InputError(error_ + " (recording into " + dir_.string() + ")");
  std::vector<FrameRecord> frames;
  for (size_t i = 0; i < stamps_ns_.size(); ++i) frames.push_back({stamps_ns_[i], FolderImageName(i), 0.0});
  WriteFolderTimes(dir_, frames);
  if (frames.size() >= 2)
    camera.rate_hz = 1e9 * (frames.size() - 1) / static_cast<double>(frames.back().t_ns - frames.front().t_ns);
  if (camera.camera.width > 0) WriteCameraYaml(dir_ / "camera.yaml", camera);
}

}  // namespace dsm
