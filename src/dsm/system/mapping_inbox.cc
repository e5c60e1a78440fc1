// SPDX-License-Identifier: MIT
// How work reaches the mapping side (MappingInbox, handover.h): inline when sequential, on the
// mapping thread in the order handed over when threaded; the reference it publishes; and the
// waits of the tracking side and the System for it.
#include <chrono>
#include <mutex>

#include "dsm/system/mapping_side.h"
#include "dsm/system/mapping_thread.h"

namespace dsm {

void MappingSide::Run(std::function<void()> job, bool keyframe) {
  if (thread_) {
    thread_->Submit(std::move(job), keyframe);
  } else {
    job();
  }
}

void MappingSide::Submit(MappingJob job) {
  const int kf = job.keyframe;
  if (!thread_) {
    RunJob(job);
    if (kf >= 0) RunFinishJob(kf);
    return;
  }
  // A keyframe is done for the tracking side once its reference is published (the first job);
  // its candidates are selected after, while tracking goes on (the second, before any later job).
  if (kf < 0) {
    thread_->Submit([this, job = std::move(job)] { RunJob(job); }, false);
  } else {
    thread_->Submit([this, job = std::move(job)] { RunJob(job); }, true, [this, kf] { RunFinishJob(kf); });
  }
}

std::shared_ptr<const TrackingReference> MappingSide::Published() const {
  std::lock_guard<std::mutex> lock(published_mutex_);
  return published_;
}

void MappingSide::PublishReference(int kf, std::vector<ReferencePoint> points) {
  Republish(MakeReference(kf, std::move(points), nullptr));
}

void MappingSide::Republish(std::shared_ptr<const TrackingReference> ref) {
  std::lock_guard<std::mutex> lock(published_mutex_);
  published_ = std::move(ref);
}

int MappingSide::KeyframesPending() const { return thread_ ? thread_->KeyframesPending() : 0; }

int MappingSide::KeyframesUnsettled() const { return thread_ ? thread_->KeyframesUnsettled() : 0; }

void MappingSide::WaitForKeyframes() {
  if (thread_) thread_->WaitForKeyframes();
}

bool MappingSide::WaitForSettledKeyframesUntil(std::chrono::steady_clock::time_point until) {
  return !thread_ || thread_->WaitForSettledKeyframesUntil(until);
}

IdleMap& MappingSide::WaitUntilIdle(bool urgent) {
  if (thread_) thread_->WaitUntilIdle(urgent);
  return *this;
}

void MappingSide::Finish() {
  if (thread_) {
    thread_->WaitUntilIdle();
    // The run ended lost, with an adjustment stopped for a relocalisation: it ends now.
    thread_->Submit(
        [this] {
          if (RunParked()) PublishTrackingReference();
        },
        false);
    thread_->WaitUntilIdle();
    stats_->keyframe_queue_max = thread_->KeyframeQueueMax();
  }
  TrackInitFrames();  // When the run ended before the map matured.
}

}  // namespace dsm
