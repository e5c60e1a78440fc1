// SPDX-License-Identifier: MIT
// The map's start: frames go to the initialiser until it finds two views (initializer.h); the
// two keyframes are built on the tracking side, everything else about them (candidates, the
// second's first bundle adjustment, the tracking of the frames buffered between them) runs on the
// mapping side.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "dsm/image/signature.h"
#include "dsm/system/mapping_thread.h"
#include "dsm/system/system.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/initializer.h"
#include "dsm/util/check.h"

namespace dsm {

using internal::MsSince;
using internal::Scale;

FrameReport System::Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure) {
  FrameReport report;
  report.index = index;
  report.status = TrackingStatus::kInitializing;
  const auto t0 = std::chrono::steady_clock::now();
  PendingFrame frame{index, t_ns, exposure, std::make_shared<const ImagePyramid>(image, options_.pyramid_levels)};
  // (Re)starts on this frame; frames waiting on an older reference stay untracked.
  const auto restart = [&](std::string reason) {
    for (const PendingFrame& p : pending_) frames_.push_back({p.t_ns, -1, SE3d()});
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
  stats_.mapping_ms.push_back(report.mapping_ms);
  return report;
}

void System::StartMap(const InitResult& init) {
  stats_.initialized_at_frame = pending_.back().index;
  // The quality levels' seed (SeedQuality), taken before the keyframes take their pyramids.
  std::vector<double> textures;
  for (const PendingFrame& p : pending_) textures.push_back(ComputeSignature(*p.pyramid).texture);
  const int k = static_cast<int>(pending_.size()) - 1;
  const PendingFrame neighbour = pending_[std::max(0, k - 1)];
  stats_.initialization = init.planar ? "planar" : "two-view";
  PendingFrame& first = pending_.front();
  PendingFrame& last = pending_.back();
  if (setup_.line_delay_s > 0.0 && last.t_ns > first.t_ns) {
    // A rolling shutter: the two keyframes are resampled as global shutters at their timestamps
    // would have seen them, the camera turning at the rate between them.
    const ReadoutTurn turn{setup_.line_delay_s, init.current_from_reference.So3().Log() /
                                                      ((last.t_ns - first.t_ns) * 1e-9)};
    for (PendingFrame* p : {&first, &last}) p->pyramid = GlobalShutterPyramid(*p->pyramid, turn);
  }
  CreateKeyframe(first.index, first.t_ns, std::move(first.pyramid), first.exposure, SE3d(), AffineBrightness{});
  CreateKeyframe(last.index, last.t_ns, std::move(last.pyramid), last.exposure, init.current_from_reference,
                 AffineBrightness{});
  // Points triangulated by the initialiser, hosted by keyframe 0.
  stats_.per_keyframe.push_back({first.index, 0, 0, {}});
  for (const InitPoint& ip : init.points) {
    Point p;
    p.host = 0;
    p.pixel = ip.pixel;
    p.idepth = ip.idepth;
    p.created_at_keyframe = 2;
    HostPatch patch;
    if (!SampleHostPatch(map_.keyframe(0).Pyramid(), 0, p.pixel, map_.interpolation(), &patch)) continue;
    map_.AddPoint(p);
    ++stats_.points_created;
    ++stats_.per_keyframe.back().points_created;
  }
  window_ = {0};
  frames_.push_back({first.t_ns, 0, SE3d()});
  // Until keyframe 1 is mapped, frames are tracked against it with the initialiser's depths.
  PublishReference(1, ReferencePointsIn(1, map_.keyframe(0).points, /*adjusted=*/false));
  // From here on the map is the mapping side's: keyframe 1's mapping (keyframe 0's candidates
  // traced in it with the initial pose, its first bundle adjustment) and what follows run there,
  // so that a live camera's next frame does not wait for them. Brightness guess: only the exposure
  // changed (alpha = log(tau_1 / tau_0), so a_1 = 0).
  const double alpha = std::log(last.exposure / first.exposure), exposure = last.exposure;
  RunOnMappingSide(
      [this, pose = init.current_from_reference, alpha, exposure] {
        SelectCandidates(0);
        TraceCandidates(map_.keyframe(1).Pyramid(), 0, pose, alpha, 0.0, exposure);
        MapNewKeyframe(1);
        FinishKeyframe(1);
      },
      /*keyframe=*/true);
  // The next frame waits for it unless frames are live (Process): the tracking residual it
  // measures is the baseline of the keyframe decision's residual rule, which frames tracked
  // against the initialiser's depths would set too high.
  waits_.for_pending_keyframe = true;
  next_keyframe_ = 2;
  last_frame_keyframe_ = 1;
  UpdateReference(false);
  Transition(TrackingEvent::kMapStarted);
  stats_.frames_tracked += 2;

  const SE3d kf1_from_kf0 = init.current_from_reference;
  std::vector<PendingFrame> between(pending_.begin() + 1, pending_.begin() + std::max(1, k));
  for (const PendingFrame& p : between) frames_.push_back({p.t_ns, -1, SE3d()});
  // Tracked once the first bundle adjustments have settled the young map (FinishKeyframe).
  init_between_ = {std::move(between), kf1_from_kf0, k};
  frames_.push_back({last.t_ns, 1, SE3d()});
  std::stable_sort(frames_.begin(), frames_.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  // Per frame index (frames dropped while starting count as well).
  const int index_steps = last.index - pending_.front().index;
  track_.velocity = index_steps > 0 ? Scale(kf1_from_kf0, 1.0 / index_steps) : SE3d();
  track_.last_trusted_index = last.index;
  track_.last_trusted_t_ns = last.t_ns;
  track_.exposure = last.exposure;
  SeedQuality(neighbour, k >= 2 ? track_.velocity.Inverse() : kf1_from_kf0.Inverse(), textures);
  pending_.clear();
}

void System::SeedQuality(const PendingFrame& neighbour, const SE3d& guess, const std::vector<double>& textures) {
  // The residual level: the frame before the second keyframe (or the first keyframe, when the
  // initialiser had no frame between them) tracked against the reference as it stands (in
  // sequential runs the second keyframe, mapped), as the next frames will be.
  const TrackResult r = tracker_->Track(*neighbour.pyramid, guess, std::log(neighbour.exposure / track_.exposure), 0.0, 1);
  track_.quality.Seed(r.ok ? r.residual_p50 : 0.0, textures);
}

void System::TrackInitFrames() {
  // Hand-held starts turn back and forth between the two keyframes (on `pan`, 60 deg away from
  // keyframe 1 and back), so an interpolation of their relative motion is no guess for the frames
  // between, and one keyframe may barely overlap the frames near the other (tracking a narrow
  // overlap confuses a tilt with a sideways shift). Each frame is therefore tracked twice, in a
  // chain forwards from keyframe 0 and backwards from keyframe 1, each from its neighbour's pose
  // and the step between them (constant velocity), and keeps the result of the keyframe it is
  // turned less from. A chain stops at its first failure. The references are the map's points as
  // the bundle adjustments of the next keyframes left them: the two-view start is only a guess.
  const std::vector<PendingFrame> between = std::move(init_between_.frames);
  init_between_.frames.clear();
  if (between.empty()) return;
  const int n = static_cast<int>(between.size());
  const auto angle = [](const std::optional<TrackResult>& r) { return r->frame_from_keyframe.So3().Log().norm(); };
  // `stop(i, r)`: the chain ends before frame i.
  std::vector<int> live;  // The young map's points, whichever keyframes the window holds by now.
  for (int pid = 0; pid < map_.NumPoints(); ++pid)
    if (!map_.point(pid).removed) live.push_back(pid);
  const auto chain = [&](int keyframe, SE3d step, bool forward, const auto& stop) {
    map_.LoadPyramids({keyframe});
    FrameTracker tracker(options_.tracker);
    tracker.SetReference(map_.keyframe(keyframe).pyramid.get(), camera_, ReferencePointsIn(keyframe, live));
    std::vector<std::optional<TrackResult>> out(n);
    SE3d previous;  // The neighbour's frame_from_keyframe.
    for (int j = 0; j < n; ++j) {
      const int i = forward ? j : n - 1 - j;
      std::optional<TrackResult> r = tracker.Track(*between[i].pyramid, step * previous, 0.0, 0.0, j + 1);
      if (!r->ok || stop(i, r)) break;
      step = r->frame_from_keyframe * previous.Inverse();
      previous = r->frame_from_keyframe;
      out[i] = std::move(r);
    }
    return out;
  };
  // Frame j + 1 from frame j, as the two-view start saw it: the chains' first guess.
  const SE3d per_frame = Scale(init_between_.kf1_from_kf0, 1.0 / init_between_.steps);
  const auto from_kf1 = chain(1, per_frame.Inverse(), false, [](int, const auto&) { return false; });
  // Forwards only while keyframe 0 is the nearer one (the tracking thread may be waiting).
  const auto from_kf0 =
      chain(0, per_frame, true, [&](int i, const auto& r) { return from_kf1[i] && angle(from_kf1[i]) <= angle(r); });
  const double baseline = InitBaseline();
  for (int i = 0; i < n; ++i) {
    const bool use_kf0 = from_kf0[i] && (!from_kf1[i] || angle(from_kf0[i]) < angle(from_kf1[i]));
    const std::optional<TrackResult>& r = use_kf0 ? from_kf0[i] : from_kf1[i];
    if (r) init_tracked_.push_back({between[i].t_ns, use_kf0 ? 0 : 1, r->frame_from_keyframe, baseline});
  }
}

void System::RunOnMappingSide(std::function<void()> job, bool keyframe) {
  if (mapping_thread_) {
    mapping_thread_->Submit(std::move(job), keyframe);
  } else {
    job();
  }
}

void System::MergeInitTracked() {
  for (const FrameRecordInternal& t : init_tracked_) {
    const auto it = std::lower_bound(frames_.begin(), frames_.end(), t.t_ns,
                                     [](const FrameRecordInternal& f, int64_t v) { return f.t_ns < v; });
    DSM_CHECK(it != frames_.end() && it->t_ns == t.t_ns, "an initialisation frame has no record");
    *it = t;
    ++stats_.frames_tracked;
  }
  init_tracked_.clear();
}

}  // namespace dsm
