// SPDX-License-Identifier: MIT
#include "dsm/run/realtime_wait.h"

#include <algorithm>
#include <cmath>

namespace dsm {

namespace {

RealtimeWait::Clock::duration Ms(double ms) {
  return std::chrono::duration_cast<RealtimeWait::Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

double Longest(const std::deque<double>& ms) { return ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()); }

// Appends `ms`, keeping the last `window` values.
void PushRecent(double ms, size_t window, std::deque<double>* recent) {
  recent->push_back(ms);
  if (recent->size() > window) recent->pop_front();
}

}  // namespace

RealtimeWait::Clock::time_point RealtimeWait::Deadline(Clock::time_point released,
                                                       std::optional<Clock::time_point> release_next,
                                                       std::optional<Clock::time_point> release_after_next) const {
  const Clock::time_point limit = Limit(released, release_after_next);
  if (!release_next) return limit;
  const double slack = std::max(0.0, kNextFirstPoseMs - BusyMs() - Longest(first_pose_ms_));
  return std::min(limit, *release_next + Ms(slack));
}

RealtimeWait::Clock::time_point RealtimeWait::Limit(Clock::time_point released,
                                                    std::optional<Clock::time_point> release_after_next) const {
  if (!(target_ms_ > 0.0)) return released;
  const bool bounded = std::isfinite(target_ms_);
  const double busy = BusyMs();
  const Clock::time_point within_target = bounded ? released + Ms(target_ms_ - busy) : released;
  if (!release_after_next) return within_target;
  const Clock::time_point no_drop = *release_after_next - Ms(busy);
  if (!bounded) return no_drop;
  const auto long_ones = std::count_if(latency_ms_.begin(), latency_ms_.end(), [&](double l) { return l > target_ms_; });
  return static_cast<double>(long_ones) < kLongShare * kLatencyWindow ? no_drop : std::min(no_drop, within_target);
}

double RealtimeWait::BusyMs() const {
  return Longest(busy_ms_) + kMarginMs;
}

void RealtimeWait::Record(double latency_ms, double busy_ms, double first_pose_ms) {
  PushRecent(busy_ms, kRecentFrames, &busy_ms_);
  PushRecent(first_pose_ms, kRecentFrames, &first_pose_ms_);
  PushRecent(latency_ms, kLatencyWindow, &latency_ms_);
}

}  // namespace dsm
