// SPDX-License-Identifier: MIT
// The realtime pace's bound on waiting for the mapping side (System::Process wait_until).
//
// A frame tracked while a keyframe is still being mapped is aligned with the keyframe before it:
// further from its reference than in the sequential run, and its candidates' traces and the next
// keyframe decision with it. A live camera's frame may wait for the pending keyframe, within these
// limits:
//  - It holds the next frame's first pose back no more than its latency budget allows: the
//    frame's own first pose was told before the wait, the next one's comes after this frame's
//    work after the wait point (b, below) and the next frame's own work up to its first pose (p:
//    the longest time from taking a frame to its first pose over the last kRecentFrames), so the
//    wait ends by r_{i+1} + kNextFirstPoseMs - b - p. (Waits up to the no-drop limit alone hold
//    first poses back; ending every wait at r_{i+1} costs accuracy.)
//  - No frame is lost by it. The camera driver keeps the newest frame, so frame i + 1 is lost only
//    if frame i is still busy when frame i + 2 arrives: frame i (released at r_i) waits at most
//    until r_{i+2} - b, with b the longest time the last kRecentFrames frames spent after their
//    wait point (FrameReport::wait_end: tracking against the newest keyframe and the hand-over to
//    the mapping side; reading the frame and a pose told before the wait come before it) plus
//    kMarginMs.
//  - Optionally, the latency of the pose the run keeps (release to it) stays within
//    `latency_target_ms` for all but a few frames: a frame may wait past r_i + target - b only
//    while fewer than kLongShare of the last kLatencyWindow frames took longer than the target. No
//    target (infinity, the default): the first limit alone. A target of 0: no wait at all.
// A frame's first pose does not wait: it is told before the wait (System::SetPoseListener).
// Near the end, with r_{i+2} unknown, only a finite target allows a wait.
// Without a target the realtime keyframes are the sequential ones wherever the mapping keeps up.
// A target makes waits end part-way, which can lose tracking where a near occluder passes: it is
// off by default.
#pragma once

#include <chrono>
#include <deque>
#include <limits>
#include <optional>

namespace dsm {

class RealtimeWait {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr size_t kRecentFrames = 30;
  static constexpr size_t kLatencyWindow = 100;
  static constexpr double kLongShare = 0.08;
  static constexpr double kMarginMs = 5.0;
  static constexpr double kNextFirstPoseMs = 45.0;

  explicit RealtimeWait(double latency_target_ms = std::numeric_limits<double>::infinity())
      : target_ms_(latency_target_ms) {}

  // How long the frame released at `released` may wait; `release_next` is r_{i+1},
  // `release_after_next` r_{i+2} (none near the end).
  Clock::time_point Deadline(Clock::time_point released, std::optional<Clock::time_point> release_next,
                             std::optional<Clock::time_point> release_after_next) const;
  // After each frame: its latency, the time it was busy after its wait point (before the map
  // starts: read and processed, wait left out), and the time from taking it to its first pose.
  void Record(double latency_ms, double busy_ms, double first_pose_ms);

 private:
  // b: the longest time the recent frames were busy after their wait point, plus kMarginMs.
  double BusyMs() const;
  // The limits but the next frame's first pose.
  Clock::time_point Limit(Clock::time_point released, std::optional<Clock::time_point> release_after_next) const;

  double target_ms_;
  std::deque<double> busy_ms_;     // The last kRecentFrames.
  std::deque<double> first_pose_ms_;  // The last kRecentFrames.
  std::deque<double> latency_ms_;  // The last kLatencyWindow.
};

}  // namespace dsm
