// SPDX-License-Identifier: MIT
// How the tracking side waits for the mapping side (a threaded System only): for the keyframe in
// flight before a frame is tracked, and in the realtime pace until a deadline, so that a frame is
// tracked against the keyframe it would have in the sequential run when the mapping side keeps up
// (run/realtime_wait.h decides the deadline). The tracking logic itself is in tracking_side.cc.
#include <chrono>

#include "dsm/system/tracking_side.h"
#include "dsm/system/system_internal.h"

namespace dsm {

using internal::MsSince;

void TrackingSide::Preview(int index, const Image<float>& input, double exposure_ms) const {
  if (!reference_ || state_ == TrackingState::kLost || !pose_listener_) return;
  const ImagePyramid pyramid(input, options_.pyramid_levels, /*gradients=*/false);
  const TrackResult result = TrackFrame(index, pyramid, exposure_ms > 0.0 ? exposure_ms : 1.0);
  if (result.ok) pose_listener_(index, WorldFromCam(result.frame_from_keyframe));
}

bool TrackingSide::WaitForMapping(FrameWork* f, std::optional<std::chrono::steady_clock::time_point> until) {
  const auto start = std::chrono::steady_clock::now();
  const std::shared_ptr<const TrackingReference> before = reference_;
  if (!until) {
    mapping_->WaitForKeyframes();
  } else if (!mapping_->WaitForSettledKeyframesUntil(*until)) {
    ++stats_->keyframe_wait_timeouts;
  }
  UpdateReference(false);
  const auto waited = std::chrono::steady_clock::now() - start;
  f->t0 += waited;  // The wait is left out of the tracking time.
  f->report.wait_ms += std::chrono::duration<double, std::milli>(waited).count();
  if (f->report.wait_end) *f->report.wait_end += waited;  // A wait after the wait point (a retrack).
  return reference_ != before;
}

void TrackingSide::WaitForNewerKeyframe(FrameWork* f, std::chrono::steady_clock::time_point until) {
  if (mapping_->KeyframesUnsettled() == 0) return;
  // A frame tracked against the keyframe before the pending one lands further from its
  // reference, and its candidates' traces and the next keyframe with it: it waits until `until`
  // and is tracked against the newer one. It waits for the adjustments after the keyframe's
  // publication as well (FinishKeyframe: the young map's, the loop's), which move the keyframe:
  // the sequential run tracks the frame against the adjusted one. A live camera's pose does not
  // wait for that: it is tracked against the newest keyframe published first and told
  // (SetPoseListener); the frame's pose the run keeps is the later one.
  ++stats_->keyframe_waits;
  if (pose_listener_ && f->reason.empty() && state_ != TrackingState::kLost) {
    TrackAndJudge(f);
    if (f->reason.empty()) {
      pose_listener_(f->index, WorldFromCam(f->result.frame_from_keyframe));
      f->report.posed_before_wait = true;
    }
  }
  if (WaitForMapping(f, until) && f->tracked) {
    f->tracked = false;
    f->reason.clear();  // Its image passed (it was tracked); the tracking is done again.
  }
}

}  // namespace dsm
