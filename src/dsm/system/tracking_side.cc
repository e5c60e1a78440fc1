// SPDX-License-Identifier: MIT
// Frame processing on the tracking side: tracking and the hand-over to the mapping side. The
// map's start is in tracking_start.cc, relocalisation in tracking_relocalisation.cc, the
// bookkeeping of lost frames in tracking_loss.cc, the waits for the mapping side in tracking_pace.cc.
#include "dsm/system/tracking_side.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "dsm/image/noise.h"
#include "dsm/image/signature.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/initializer.h"
#include "dsm/tracking/rolling_shutter.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

using internal::FrameBrightness;
using internal::MsSince;
using internal::Scale;

}  // namespace

std::string TrackingStatusName(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kInitializing: return "initializing";
    case TrackingStatus::kOk: return "ok";
    case TrackingStatus::kLost: return "lost";
  }
  return "?";
}

TrackingSide::TrackingSide(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup,
                           TrackingStats* stats, MappingInbox* mapping)
    : camera_(camera),
      options_(options),
      setup_(setup),
      stats_(stats),
      mapping_(mapping),
      initializer_(std::make_unique<Initializer>(options.initializer)),
      tracker_(std::make_unique<FrameTracker>(options.tracker)) {
  track_.quality = TrackingQuality(options.quality);
}

TrackingSide::~TrackingSide() = default;

bool TrackingSide::ReferenceIsStale() const { return mapping_->Published() != reference_; }

FrameReport TrackingSide::Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                            std::optional<std::chrono::steady_clock::time_point> wait_until) {
  DSM_CHECK(!suspended_ || state_ == TrackingState::kLost || state_ == TrackingState::kConfirming,
            "a suspended map is lost");
  NoteTimestamp(index, t_ns);
  if (!suspended_) ++stats_->frames;  // A suspended map's frame counts once it is tracked.
  const double exposure = exposure_ms > 0.0 ? exposure_ms : 1.0;
  if (state_ == TrackingState::kInitializing) return Initialize(index, t_ns, image, exposure);

  // The paper's tracking thread: the frame is aligned with the newest keyframe the mapping side
  // has finished and judged by the quality test (tracking_quality.h): the image first, then the
  // alignment; while lost it is aligned with the keyframes most like it instead (tracking_state.h).
  FrameWork f = BeginFrame(index, t_ns, image, exposure);
  if (wait_until && !f.waited) WaitForNewerKeyframe(&f, *wait_until);  // tracking_pace.cc
  f.report.wait_end = std::chrono::steady_clock::now();
  if (state_ != TrackingState::kLost && (f.tracked || f.reason.empty())) TrackAgainstReference(&f);
  if (state_ == TrackingState::kConfirming && !f.reason.empty()) WithdrawRelocalisation();
  if (state_ == TrackingState::kLost && f.reason.empty()) TryRelocalise(&f);
  f.report.tracking_ms = MsSince(f.t0);
  if (!f.reason.empty()) return LostFrame(std::move(f.report), t_ns, std::move(f.reason));
  AcceptPose(&f);
  // A relocalised frame's pose is tentative: it feeds nothing to the mapping side.
  if (!f.report.relocalised) HandToMappingSide(&f);
  return f.report;
}

void TrackingSide::Transition(TrackingEvent event) {
  const std::optional<TrackingState> next = NextTrackingState(state_, event);
  DSM_CHECK(next.has_value(), "the tracking state has no such transition");
  state_ = *next;
}

TrackingSide::FrameWork TrackingSide::BeginFrame(int index, int64_t t_ns, const Image<float>& image, double exposure) {
  FrameWork f;
  f.index = index;
  f.t_ns = t_ns;
  f.exposure = exposure;
  f.report.index = index;
  // What the frame before asked for (PendingWaits): the keyframe in flight first, or after a
  // relocalisation the one made from the confirming frame: even a live camera waits for that, or
  // tracking would drift off the old keyframe meanwhile.
  const auto wait_start = std::chrono::steady_clock::now();
  f.waited = (waits_.for_pending_keyframe && setup_.wait_for_mapping) || waits_.for_confirming_keyframe;
  UpdateReference(f.waited);
  waits_.for_confirming_keyframe = false;
  f.report.wait_ms = MsSince(wait_start);
  f.t0 = std::chrono::steady_clock::now();
  f.pyramid = std::make_shared<const ImagePyramid>(image, options_.pyramid_levels, /*gradients=*/false);
  f.signature = ComputeSignature(*f.pyramid);
  f.previous_texture = previous_texture_;
  previous_texture_ = f.signature.texture;
  f.reason = track_.quality.CheckImage(f.signature.texture);
  return f;
}

void TrackingSide::TrackAndJudge(FrameWork* f) {
  f->result = TrackFrame(f->index, *f->pyramid, f->exposure);
  f->tracked = true;
  if (f->result.brightness_held) ++stats_->brightness_holds;
  f->reason = track_.quality.CheckTracking(f->result,
                                           f->result.frame_from_keyframe * track_.last_frame_from_reference.Inverse(),
                                           FramesSinceTrusted(f->index), tracker_->MeanIdepth());
  // A relocalisation is confirmed by an alignment that found its own way, not by one that fell
  // into the flat prediction and was done again with the brightness held: its pose passes a
  // residual level the relocalisation has just restarted at its own value.
  if (f->reason.empty() && state_ == TrackingState::kConfirming && f->result.brightness_held)
    f->reason = "brightness held right after a relocalisation";
}

void TrackingSide::TrackAgainstReference(FrameWork* f) {
  if (!f->tracked) {
    UpdateReference(false);  // A keyframe may have been published since the frame came in.
    TrackAndJudge(f);
  }
  if (!f->reason.empty() && mapping_->KeyframesPending() > 0) {
    // Failed against the keyframe before the one being mapped (a wait that ended first): the
    // newer keyframe may see what the camera sees now. Waiting for it costs this frame some
    // latency; a lost frame would cost a relocalisation, which waits for the mapping side too.
    ++stats_->keyframe_retracks;
    WaitForMapping(f, std::nullopt);
    TrackAndJudge(f);
  }
  if (!f->reason.empty() && state_ == TrackingState::kConfirming) {
    // Not confirmed: the relocalisation is withdrawn and this frame is tried against the map.
    WithdrawRelocalisation();
    f->reason.clear();
  }
}

void TrackingSide::TryRelocalise(FrameWork* f) {
  // A frame with less than the usual texture may be half hidden by a hand sliding off the lens,
  // where any pose fits the rest as well as the right one: it re-anchors the camera only by
  // three sightings that move as one camera.
  const std::string plain = track_.quality.CheckRelocalisationImage(f->signature.texture, reference_->texture);
  Tentative before = SaveTentative(f->index);
  f->report.relocalised = Relocalise(f->index, *f->pyramid, f->signature, f->exposure, plain, &f->result,
                                     &f->relocalised_velocity, &f->reason, &before.evidence);
  if (f->report.relocalised) {
    tentative_ = std::move(before);
    Transition(TrackingEvent::kRelocalised);
  } else {
    ++track_.failed_relocalisations;
  }
}

void TrackingSide::AcceptPose(FrameWork* f) {
  const TrackResult& result = f->result;
  const bool confirmed = state_ == TrackingState::kConfirming && !f->report.relocalised;
  if (confirmed) {
    stats_->relocalised.push_back(tentative_->evidence);
    tentative_.reset();
    ++stats_->relocalisations;
  }
  if (!f->report.relocalised) Transition(TrackingEvent::kTracked);
  f->confirmed = confirmed;
  if (suspended_) {
    ++stats_->frames;
    if (confirmed) {
      suspended_ = false;
      f->report.resumed = true;
    }
  }
  track_.lost_in_a_row = track_.failed_relocalisations = 0;
  // A relocalised frame's reference is another keyframe than the last trusted frame's: its
  // velocity comes from Relocalise.
  CommitPose(f->index, result, f->exposure,
             f->report.relocalised ? std::optional<SE3d>(f->relocalised_velocity) : std::nullopt);
  if (f->report.relocalised) {
    track_.quality.Restart(result.residual_p50, f->signature.texture);
  } else {
    track_.quality.Trust(result.residual_p50, f->signature.texture, result.inlier_ratio);
  }
  last_frame_keyframe_ = -1;
  f->report.status = TrackingStatus::kOk;
  f->report.tracking_rmse = result.rmse;
  ++stats_->frames_tracked;
  frames_.push_back({f->t_ns, reference_->keyframe, result.frame_from_keyframe, 0.0, reference_->scale});
  if (pose_listener_ && !f->report.posed_before_wait) pose_listener_(f->index, *LastFramePose());
  stats_->tracking_ms.push_back(f->report.tracking_ms);
}

void TrackingSide::HandToMappingSide(FrameWork* f) {
  const TrackResult& result = f->result;
  if (track_.first_rmse_after_keyframe == 0.0) track_.first_rmse_after_keyframe = result.rmse;
  KeyframeScores scores;
  scores.parallax = result.frame_from_keyframe.Translation().norm() * tracker_->MeanIdepth();
  scores.visibility = result.visibility;
  scores.brightness = std::abs(result.alpha - std::log(f->exposure / reference_->exposure[reference_->keyframe]));
  scores.rmse = result.rmse;
  scores.first_rmse = track_.first_rmse_after_keyframe;

  MappingJob job;
  job.index = f->index;
  job.t_ns = f->t_ns;
  job.exposure = f->exposure;
  job.pyramid = std::move(f->pyramid);
  job.reference = reference_->keyframe;
  job.frame_from_reference = result.frame_from_keyframe;
  job.alpha = result.alpha;
  job.beta = result.beta;
  job.relocalisations = stats_->relocalisations;
  job.readout = Readout();  // With the step to this frame: the mapping side's image is rectified.
  waits_.for_pending_keyframe = false;
  if (ShouldCreateKeyframe(scores, options_.keyframe) &&
      track_.quality.CheckKeyframeImage(f->signature.texture, f->previous_texture)) {
    if (mapping_->threaded() && (mapping_->KeyframesPending() > 0 || ReferenceIsStale())) {
      // Another keyframe is in flight, or was published while this frame was tracked against the
      // one before it: a keyframe made from this frame would hang off the older keyframe, next
      // to the newer one. The next frame waits for the pending keyframe (or not) and decides again.
      waits_.for_pending_keyframe = true;
    } else {
      job.keyframe = next_keyframe_++;
      // Its error model starts as the one fitted to its tracking residuals: it judges which map
      // points the keyframe sees before the PBA (TrackingSide::SeenIn), which then refits it.
      job.model = options_.tracker.robust.kind == options_.pba.robust.kind ? result.model
                                                                           : DefaultErrorModel(options_.pba.robust);
      job.rmse = result.rmse;
      job.inlier_ratio = result.inlier_ratio;
      frames_.back() = {f->t_ns, job.keyframe, SE3d()};
      last_frame_keyframe_ = job.keyframe;
      f->report.keyframe = true;
      waits_.for_confirming_keyframe = f->confirmed;
    }
  }
  if (job.keyframe < 0 && setup_.skip_traces_while_mapping && mapping_->KeyframesPending() > 0) {
    ++stats_->traces_skipped;  // Its relocalisation count reaches the mapping side with the next job.
    return;
  }
  const auto t1 = std::chrono::steady_clock::now();
  mapping_->Submit(std::move(job));
  if (!mapping_->threaded()) f->report.mapping_ms = MsSince(t1);
}

void TrackingSide::UpdateReference(bool wait) {
  if (mapping_->threaded() && wait) {
    ++stats_->keyframe_waits;
    mapping_->WaitForKeyframes();
  }
  std::shared_ptr<const TrackingReference> next = mapping_->Published();
  if (next == reference_) return;
  if (reference_ && last_frame_keyframe_ != next->keyframe) {
    // The last frame is not the new reference keyframe (it was made while tracking went on, the
    // last frame was lost, or the same keyframe comes back adjusted, as keyframe 1 does after the
    // start): its pose and brightness move from the old reference to it.
    // Both keyframes as the new snapshot has them (the bundle adjustment moved both since).
    const int o = reference_->keyframe, n = next->keyframe;
    track_.last_frame_from_reference =
        track_.last_frame_from_reference * next->cam_from_world[o] * next->cam_from_world[n].Inverse();
    // Absolute brightness of the last frame, then relative to the new reference.
    const AffineBrightness f =
        FrameBrightness(next->affine[o], next->exposure[o], track_.alpha, track_.beta, track_.exposure);
    internal::RelativeBrightness(f, track_.exposure, next->affine[n], next->exposure[n], &track_.alpha, &track_.beta);
  } else {
    // The new reference is the keyframe made from the last tracked frame.
    track_.last_frame_from_reference = SE3d();
    track_.alpha = 0.0;
    track_.beta = 0.0;
  }
  reference_ = std::move(next);
  tracker_->SetReference(reference_->pyramid.get(), camera_, reference_->points);
  track_.first_rmse_after_keyframe = 0.0;
}

ReadoutTurn TrackingSide::Readout() const {
  if (!(setup_.line_delay_s > 0.0 && frame_interval_ns_ > 0.0 && HasTrustedFrame())) return {};
  return {setup_.line_delay_s, track_.velocity.So3().Log() / (frame_interval_ns_ * 1e-9)};
}

TrackResult TrackingSide::TrackFrame(int index, const ImagePyramid& pyramid, double exposure) const {
  // Relative brightness guess: the last one, corrected for the change of exposure time.
  const double alpha_guess = track_.alpha + std::log(exposure / track_.exposure);
  // Guesses of frame_from_reference: constant velocity first, then alternatives.
  const SE3d last = track_.last_frame_from_reference;
  const int gap = FramesSinceTrusted(index);
  const SE3d step = internal::ScaleSteps(track_.velocity, gap);  // Over the frames since the last.
  std::vector<SE3d> guesses = {step * last, last, step * step * last, Scale(step, 0.5) * last};
  for (double angle : {0.02, -0.02})
    for (int axis = 0; axis < 3; ++axis) guesses.push_back(internal::RotationAbout(axis, angle) * step * last);
  std::vector<std::pair<double, int>> ranked;
  for (size_t g = 0; g < guesses.size(); ++g)
    ranked.emplace_back(tracker_->CoarseEnergy(pyramid, guesses[g], alpha_guess, track_.beta), static_cast<int>(g));
  // Constant velocity stays first unless another guess is clearly better.
  std::stable_sort(ranked.begin() + 1, ranked.end());
  if (ranked[1].first < 0.7 * ranked[0].first) std::swap(ranked[0], ranked[1]);
  const auto track = [&](int attempt) {
    return tracker_->Track(pyramid, guesses[ranked[attempt].second], alpha_guess, track_.beta, gap,
                           state_ == TrackingState::kTracking ? Readout() : ReadoutTurn{});
  };
  // Other guesses only when the first failed or left a much larger residual than usual (about a
  // fifth of the frames: the residual grows until the next keyframe). The second and third are
  // aligned concurrently, then taken in order as if one after the other: the third only counts
  // when the second did not settle it, so the result is the same.
  TrackResult best = track(0);
  const auto settled = [&] {
    return best.ok && (track_.first_rmse_after_keyframe == 0.0 || best.rmse < 2.0 * track_.first_rmse_after_keyframe);
  };
  if (settled()) return best;
  std::array<TrackResult, 2> other;
  tbb::parallel_invoke([&] { other[0] = track(1); }, [&] { other[1] = track(2); });
  for (const TrackResult& r : other) {
    if (r.ok && (!best.ok || r.rmse < best.rmse)) best = r;
    if (settled()) break;
  }
  return best;
}

void TrackingSide::CommitPose(int index, const TrackResult& result, double exposure, std::optional<SE3d> velocity) {
  const int gap = FramesSinceTrusted(index);
  const SE3d step = result.frame_from_keyframe * track_.last_frame_from_reference.Inverse();
  track_.velocity = velocity ? *velocity : internal::ScaleSteps(step, 1.0 / gap);
  track_.last_trusted_index = index;
  track_.last_trusted_t_ns = current_t_ns_;
  track_.last_frame_from_reference = result.frame_from_keyframe;
  track_.alpha = result.alpha;
  track_.beta = result.beta;
  track_.exposure = exposure;
}

std::optional<SE3d> TrackingSide::LastFramePose() const {
  if (!reference_ || reference_->keyframe < 0) return std::nullopt;
  return WorldFromCam(track_.last_frame_from_reference);
}

SE3d TrackingSide::WorldFromCam(const SE3d& frame_from_reference) const {
  // cam_from_world of the frame = frame_from_reference * reference's cam_from_world.
  return (frame_from_reference * reference_->cam_from_world[reference_->keyframe]).Inverse();
}

void TrackingSide::MergeFrames(const std::vector<FramePose>& other, int offset, double other_baseline,
                               int num_keyframes) {
  // Relative to their keyframes as before (their offsets scale with the keyframe:
  // MappingSide::KeyframeScale), the initial keyframes' distance as the other map had it.
  std::vector<FramePose> merged;
  for (FramePose f : other) {
    if (f.reference < 0) continue;
    f.frame_from_reference = f.AtBaseline(other_baseline);
    f.init_baseline = 0.0;
    f.reference += offset;
    merged.push_back(f);
  }
  std::vector<FramePose> all;
  std::merge(merged.begin(), merged.end(), frames_.begin(), frames_.end(), std::back_inserter(all),
             [](const FramePose& a, const FramePose& b) { return a.t_ns < b.t_ns; });
  frames_ = std::move(all);
  next_keyframe_ = num_keyframes;
}

void TrackingSide::TakeUpLoadedMap(int num_keyframes, double speed, double residual_level, double texture_level) {
  DSM_CHECK(state_ == TrackingState::kInitializing && seen_index_ < 0,
            "a map is taken up by a new System, before its first frame");
  next_keyframe_ = num_keyframes;
  loaded_speed_ = speed;
  track_ = TrackingHistory{};
  track_.quality = TrackingQuality(options_.quality);
  track_.quality.Seed(residual_level,
                      std::vector<double>(texture_level > 0.0 ? options_.quality.min_history : 0, texture_level));
  reference_ = mapping_->Published();
  track_.exposure = reference_->exposure[reference_->keyframe];
  tracker_->SetReference(reference_->pyramid.get(), camera_, reference_->points);
  track_.first_rmse_after_keyframe = 0.0;
  Transition(TrackingEvent::kMapLoaded);
  suspended_ = true;
}

}  // namespace dsm
