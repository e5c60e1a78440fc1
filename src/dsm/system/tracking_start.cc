// SPDX-License-Identifier: MIT
// The map's start on the tracking side: frames go to the initialiser until it finds two views
// (initializer.h), then the two keyframes, the initialiser's points and the frames between them
// go to the mapping side (MapStart; mapping_start.cc builds the map from them).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "dsm/image/signature.h"
#include "dsm/system/tracking_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/initializer.h"
#include "dsm/util/check.h"

namespace dsm {

using internal::MsSince;
using internal::Scale;

FrameReport TrackingSide::Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure) {
  FrameReport report;
  report.index = index;
  report.status = TrackingStatus::kInitializing;
  const auto t0 = std::chrono::steady_clock::now();
  InitFrame frame{index, t_ns, exposure, std::make_shared<const ImagePyramid>(image, options_.pyramid_levels)};
  // (Re)starts on this frame; frames waiting on an older reference stay untracked.
  const auto restart = [&](std::string reason) {
    for (const InitFrame& p : pending_) frames_.push_back({p.t_ns, -1, SE3d()});
    pending_.clear();
    initializer_->SetReference(image, camera_);
    pending_.push_back(std::move(frame));
    report.reason = std::move(reason);
    return report;
  };
  if (!initializer_->HasReference() || static_cast<int>(pending_.size()) >= options_.max_initialization_frames)
    return restart("waiting for motion");
  const InitResult init = initializer_->AddFrame(image);
  // Too few corners left to join two views (InitializerOptions::min_track_share), whether or not
  // they would: this frame becomes the reference.
  if (initializer_->TrackShare() < options_.initializer.min_track_share) {
    char share[64];
    std::snprintf(share, sizeof(share), "%.0f%%", 100.0 * initializer_->TrackShare());
    return restart(std::string("most corners lost (") + share + " left): starting over");
  }
  pending_.push_back(std::move(frame));
  if (!init.ok) {
    report.reason = init.reason;
    return report;
  }
  StartMap(init);
  report.status = TrackingStatus::kOk;
  report.keyframe = true;
  report.mapping_ms = MsSince(t0);
  return report;
}

void TrackingSide::StartMap(const InitResult& init) {
  stats_->initialized_at_frame = pending_.back().index;
  // The quality levels' seed (SeedQuality), taken before the keyframes take their pyramids.
  std::vector<double> textures;
  for (const InitFrame& p : pending_) textures.push_back(ComputeSignature(*p.pyramid).texture);
  const int k = static_cast<int>(pending_.size()) - 1;
  const InitFrame neighbour = pending_[std::max(0, k - 1)];
  stats_->initialization = init.planar ? "planar" : "two-view";
  MapStart start;
  start.first = pending_.front();
  start.last = pending_.back();
  if (setup_.line_delay_s > 0.0 && start.last.t_ns > start.first.t_ns) {
    // A rolling shutter: the two keyframes are resampled as global shutters at their timestamps
    // would have seen them, the camera turning at the rate between them.
    const ReadoutTurn turn{setup_.line_delay_s, init.current_from_reference.So3().Log() /
                                                      ((start.last.t_ns - start.first.t_ns) * 1e-9)};
    for (InitFrame* p : {&start.first, &start.last})
      p->pyramid = internal::GlobalShutterPyramid(*p->pyramid, camera_, turn, options_.pyramid_levels);
  }
  const InitFrame first = start.first, last = start.last;
  const SE3d kf1_from_kf0 = init.current_from_reference;
  start.kf1_from_kf0 = kf1_from_kf0;
  start.points = init.points;
  // The frames between the keyframes are tracked by the mapping side once the first bundle
  // adjustments have settled the young map.
  start.between.assign(pending_.begin() + 1, pending_.begin() + std::max(1, k));
  start.steps = k;
  for (const InitFrame& p : start.between) frames_.push_back({p.t_ns, -1, SE3d()});
  // The map is the mapping side's from here on: keyframe 1's mapping (keyframe 0's candidates
  // traced in it with the initial pose, its first bundle adjustment) and what follows run there,
  // so that a live camera's next frame does not wait for them.
  mapping_->StartMap(std::move(start));
  frames_.push_back({first.t_ns, 0, SE3d()});
  // The next frame waits for it unless frames are live (Process): the tracking residual it
  // measures is the baseline of the keyframe decision's residual rule, which frames tracked
  // against the initialiser's depths would set too high.
  waits_.for_pending_keyframe = true;
  next_keyframe_ = 2;
  last_frame_keyframe_ = 1;
  UpdateReference(false);
  Transition(TrackingEvent::kMapStarted);
  stats_->frames_tracked += 2;
  frames_.push_back({last.t_ns, 1, SE3d()});
  std::stable_sort(frames_.begin(), frames_.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  // Per frame index (frames dropped while starting count as well).
  const int index_steps = last.index - first.index;
  track_.velocity = index_steps > 0 ? Scale(kf1_from_kf0, 1.0 / index_steps) : SE3d();
  track_.last_trusted_index = last.index;
  track_.last_trusted_t_ns = last.t_ns;
  track_.exposure = last.exposure;
  SeedQuality(neighbour, k >= 2 ? track_.velocity.Inverse() : kf1_from_kf0.Inverse(), textures);
  pending_.clear();
}

void TrackingSide::SeedQuality(const InitFrame& neighbour, const SE3d& guess, const std::vector<double>& textures) {
  // The residual level: the frame before the second keyframe (or the first keyframe, when the
  // initialiser had no frame between them) tracked against the reference as it stands (in
  // sequential runs the second keyframe, mapped), as the next frames will be.
  const TrackResult r = tracker_->Track(*neighbour.pyramid, guess, std::log(neighbour.exposure / track_.exposure), 0.0, 1);
  track_.quality.Seed(r.ok ? r.residual_p50 : 0.0, textures);
}

void TrackingSide::MergeInitTracked(std::vector<FramePose> tracked) {
  for (const FramePose& t : tracked) {
    const auto it = std::lower_bound(frames_.begin(), frames_.end(), t.t_ns,
                                     [](const FramePose& f, int64_t v) { return f.t_ns < v; });
    DSM_CHECK(it != frames_.end() && it->t_ns == t.t_ns, "an initialisation frame has no record");
    *it = t;
    ++stats_->frames_tracked;
  }
}

}  // namespace dsm
