// SPDX-License-Identifier: MIT
#include "dsm/system/mapping_thread.h"

#include <algorithm>

#include <tbb/task_arena.h>

namespace dsm {

MappingThread::MappingThread() : thread_([this] { Loop(); }) {}

MappingThread::~MappingThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  thread_.join();
}

void MappingThread::Submit(Job job, bool keyframe, Job then) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    RethrowLocked();
    queue_.push_back({std::move(job), keyframe, keyframe && !then});
    if (then) queue_.push_back({std::move(then), false, keyframe});
    if (keyframe) {
      keyframe_queue_max_ = std::max(keyframe_queue_max_, ++keyframes_pending_);
      ++keyframes_unsettled_;
    }
  }
  work_.notify_one();
}

int MappingThread::KeyframesPending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_pending_;
}

int MappingThread::KeyframesUnsettled() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_unsettled_;
}

int MappingThread::KeyframeQueueMax() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframe_queue_max_;
}

void MappingThread::WaitForKeyframes() {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return keyframes_pending_ == 0 || error_; });
  RethrowLocked();
}

bool MappingThread::WaitForSettledKeyframesUntil(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  const bool none = done_.wait_until(lock, deadline, [this] { return keyframes_unsettled_ == 0 || error_; });
  RethrowLocked();
  return none;
}

void MappingThread::WaitUntilIdle(bool urgent) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (urgent) ++urgent_waiters_;
  done_.wait(lock, [this] { return (queue_.empty() && !running_) || error_; });
  if (urgent) --urgent_waiters_;
  RethrowLocked();
}

bool MappingThread::Urgent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return urgent_waiters_ > 0;
}

void MappingThread::RethrowLocked() {
  if (error_) std::rethrow_exception(error_);
}

void MappingThread::Loop() {
  tbb::task_arena arena;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // Stopping, and nothing left to do.
    Entry entry = std::move(queue_.front());
    queue_.pop_front();
    running_ = true;
    lock.unlock();
    std::exception_ptr error;
    if (!error_) {
      try {
        arena.execute([&] { entry.job(); });
      } catch (...) {
        error = std::current_exception();
      }
    }
    lock.lock();
    running_ = false;
    if (error && !error_) error_ = error;
    if (entry.keyframe) --keyframes_pending_;
    if (entry.settles) --keyframes_unsettled_;
    done_.notify_all();
  }
}

}  // namespace dsm
