// SPDX-License-Identifier: MIT
// The bookkeeping of lost frames: the recording's frame clock (frames missing from it count by
// their timestamps), lost episodes, the tentative relocalisation and its withdrawal, and when a
// map is given up (System::NeedsNewMap). The relocalisation itself is in tracking_relocalisation.cc.
#include <algorithm>
#include <cmath>
#include <vector>

#include "dsm/system/tracking_side.h"
#include "dsm/util/median.h"

namespace dsm {

int TrackingSide::FramesSinceTrusted(int index) const {
  if (!HasTrustedFrame()) return 1;
  int frames = std::max(1, index - track_.last_trusted_index);
  // A gap in the recording's timestamps (frames missing from it) counts as the frames that would
  // have filled it: the camera moved on meanwhile.
  if (frame_interval_ns_ > 0.0 && current_t_ns_ > track_.last_trusted_t_ns) {
    const double intervals = static_cast<double>(current_t_ns_ - track_.last_trusted_t_ns) / frame_interval_ns_;
    frames = std::max(frames, static_cast<int>(std::min(std::round(intervals), 1e6)));
  }
  return frames;
}

void TrackingSide::NoteTimestamp(int index, int64_t t_ns) {
  if (seen_index_ >= 0 && (index <= seen_index_ || t_ns <= seen_t_ns_)) {
    throw InputError("frame " + std::to_string(index) + " at t_ns " + std::to_string(t_ns) +
                     " does not come after frame " + std::to_string(seen_index_) + " at t_ns " +
                     std::to_string(seen_t_ns_) + ": frames must come in time order");
  }
  // The recording's frame interval: the median over the last steps between frames taken in turn
  // (per index step: frames dropped or skipped between them share it).
  constexpr size_t kSteps = 15;
  if (seen_index_ >= 0) {
    interval_steps_.push_back(static_cast<double>(t_ns - seen_t_ns_) / (index - seen_index_));
    if (interval_steps_.size() > kSteps) interval_steps_.pop_front();
    frame_interval_ns_ = Median(std::vector<double>(interval_steps_.begin(), interval_steps_.end()));
  }
  seen_index_ = index;
  seen_t_ns_ = t_ns;
  current_t_ns_ = t_ns;
}

FrameReport TrackingSide::LostFrame(FrameReport report, int64_t t_ns, std::string reason) {
  report.status = TrackingStatus::kLost;
  report.reason = std::move(reason);
  ++track_.lost_in_a_row;
  const bool opens_episode = state_ == TrackingState::kTracking;
  Transition(TrackingEvent::kFailed);
  if (suspended_) return report;  // Not its frame (Suspend).
  frames_.push_back({t_ns, -1, SE3d()});
  ++stats_->frames_lost;
  if (opens_episode) stats_->lost_episodes.push_back({report.index, report.index});
  stats_->lost_episodes.back().second = report.index;
  return report;
}

TrackingSide::Tentative TrackingSide::SaveTentative(int index) const {
  return Tentative{index, frames_.size(), reference_, track_, {}};
}

void TrackingSide::WithdrawRelocalisation() {
  Tentative& t = *tentative_;
  if (suspended_) {
    // Not its frame after all (Suspend): no trace left.
    frames_.resize(t.record);
    --stats_->frames_tracked;
    --stats_->frames;
  } else {
    // The relocalised frame becomes a lost one of the same episode.
    frames_[t.record].reference = -1;
    --stats_->frames_tracked;
    ++stats_->frames_lost;
    stats_->lost_episodes.back().second = t.index;
  }
  // The mapping side is idle: it was handed nothing since the camera was lost.
  if (reference_ != t.reference) AdoptReference(t.reference, mapping_->WaitUntilIdle(/*urgent=*/false));
  track_ = t.state;
  ++track_.lost_in_a_row;
  ++track_.failed_relocalisations;
  tentative_.reset();
  Transition(TrackingEvent::kWithdrawn);
}

bool TrackingSide::NeedsNewMap(bool young) const {
  const RelocalisationOptions& o = options_.relocalisation;
  if (o.max_lost_frames == 0) return false;
  const int limit = young ? std::max(1, std::min(o.max_lost_frames, o.max_predicted_frames)) : o.max_lost_frames;
  return track_.failed_relocalisations >= limit;
}

}  // namespace dsm
