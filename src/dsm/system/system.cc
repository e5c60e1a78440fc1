// SPDX-License-Identifier: MIT
// Frame processing: tracking and the hand-over to the mapping side. The map's start is in
// system_start.cc, keyframe mapping in system_mapping.cc, relocalisation in
// system_relocalisation.cc, the bookkeeping of lost frames in system_loss.cc.
#include "dsm/system/system.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "dsm/image/noise.h"
#include "dsm/image/signature.h"
#include "dsm/system/mapping_thread.h"
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

AffineBrightness FrameBrightness(const Keyframe& ref, double alpha, double beta, double exposure) {
  return internal::FrameBrightness(ref.affine, ref.exposure, alpha, beta, exposure);
}

}  // namespace

std::string TrackingStatusName(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kInitializing: return "initializing";
    case TrackingStatus::kOk: return "ok";
    case TrackingStatus::kLost: return "lost";
  }
  return "?";
}

System::System(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup)
    : camera_(camera),
      options_(options),
      setup_(setup),
      min_activation_distance_px_(options.activation.initial_min_distance_px) {
  options_.Validate();
  setup_.Validate();
  track_.quality = TrackingQuality(options.quality);
  if (options_.loop_closure.enabled && options_.mode == MapMode::kFull) {
    if (options_.loop_closure.vocabulary.empty()) {
      loop_.vocabulary = &Vocabulary::BuiltIn();
    } else {
      loop_.own_vocabulary = std::make_unique<Vocabulary>(Vocabulary::Read(options_.loop_closure.vocabulary));
      loop_.vocabulary = loop_.own_vocabulary.get();
    }
  }
  if (options_.mode == MapMode::kSlidingWindow) {
    // DSM-SW: the same window size N_w = N_t + N_c, all of it temporal (a sliding window as DSO's).
    options_.window.temporal_keyframes += options_.window.covisible_keyframes;
    options_.window.covisible_keyframes = 0;
  }
  const int div = 1 << (options_.pyramid_levels - 1);
  if (camera.width % div || camera.height % div) {
    throw InputError("the undistorted image size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                     " must divide by 2^(pyramid_levels - 1) = " + std::to_string(div));
  }
  initializer_ = std::make_unique<Initializer>(options_.initializer);
  tracker_ = std::make_unique<FrameTracker>(options_.tracker);
  if (setup_.threaded) mapping_thread_ = std::make_unique<MappingThread>();
}

System::~System() = default;

void System::ChooseNoiseHandling(double noise_sigma) {
  stats_.image_noise_sigma = noise_sigma;
  if (stats_.image_noise_sigma < options_.candidates.contrast_min_noise) options_.candidates.contrast_factor = 0.f;
  stats_.contrast_floor = options_.candidates.contrast_factor > 0.f;
  bool bspline = options_.interpolation == "bspline" ||
                 (options_.interpolation == "auto" && stats_.image_noise_sigma >= options_.bspline_min_noise);
  // A loaded map's points were sampled its way: it keeps it.
  if (map_.NumPoints() > 0) bspline = map_.interpolation() == Interpolation::kBSpline;
  if (map_.NumPoints() == 0) map_.set_interpolation(bspline ? Interpolation::kBSpline : Interpolation::kBilinear);
  stats_.interpolation = bspline ? "bspline" : "bilinear";
  TextureLossOptions& texture = options_.pba.texture_loss;
  if (options_.mode == MapMode::kFull && options_.texture_loss_min_noise > 0.0 &&
      stats_.image_noise_sigma >= options_.texture_loss_min_noise)
    texture.max_variance_ratio = kTextureLossRatio;
  stats_.texture_loss = texture.max_variance_ratio > 0.0;
}

FrameReport System::Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                            std::optional<std::chrono::steady_clock::time_point> wait_until) {
  DSM_CHECK(image.width() == camera_.width && image.height() == camera_.height, "frame size differs from the camera");
  DSM_CHECK(!suspended_ || state_ == TrackingState::kLost || state_ == TrackingState::kConfirming,
            "a suspended map is lost");
  NoteTimestamp(index, t_ns);
  if (!suspended_) ++stats_.frames;  // A suspended map's frame counts once it is tracked.
  const double exposure = exposure_ms > 0.0 ? exposure_ms : 1.0;
  if (stats_.image_noise_sigma < 0.0) ChooseNoiseHandling(EstimateNoiseSigma(image));
  if (state_ == TrackingState::kInitializing) return Initialize(index, t_ns, image, exposure);

  // The paper's tracking thread: the frame is aligned with the newest keyframe the mapping side
  // has finished and judged by the quality test (tracking_quality.h): the image first, then the
  // alignment; while lost it is aligned with the keyframes most like it instead (tracking_state.h).
  FrameWork f = BeginFrame(index, t_ns, image, exposure);
  if (wait_until && !f.waited) WaitForNewerKeyframe(&f, *wait_until);  // system_pace.cc
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

void System::Transition(TrackingEvent event) {
  const std::optional<TrackingState> next = NextTrackingState(state_, event);
  DSM_CHECK(next.has_value(), "the tracking state has no such transition");
  state_ = *next;
}

System::FrameWork System::BeginFrame(int index, int64_t t_ns, const Image<float>& image, double exposure) {
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

void System::TrackAndJudge(FrameWork* f) {
  f->result = TrackFrame(f->index, *f->pyramid, f->exposure);
  f->tracked = true;
  if (f->result.brightness_held) ++stats_.brightness_holds;
  f->reason = track_.quality.CheckTracking(f->result,
                                           f->result.frame_from_keyframe * track_.last_frame_from_reference.Inverse(),
                                           FramesSinceTrusted(f->index), tracker_->MeanIdepth());
  // A relocalisation is confirmed by an alignment that found its own way, not by one that fell
  // into the flat prediction and was done again with the brightness held: its pose passes a
  // residual level the relocalisation has just restarted at its own value.
  if (f->reason.empty() && state_ == TrackingState::kConfirming && f->result.brightness_held)
    f->reason = "brightness held right after a relocalisation";
}

void System::TrackAgainstReference(FrameWork* f) {
  if (!f->tracked) {
    UpdateReference(false);  // A keyframe may have been published since the frame came in.
    TrackAndJudge(f);
  }
  if (!f->reason.empty() && mapping_thread_ && mapping_thread_->KeyframesPending() > 0) {
    // Failed against the keyframe before the one being mapped (a wait that ended first): the
    // newer keyframe may see what the camera sees now. Waiting for it costs this frame some
    // latency; a lost frame would cost a relocalisation, which waits for the mapping side too.
    ++stats_.keyframe_retracks;
    WaitForMapping(f, std::nullopt);
    TrackAndJudge(f);
  }
  if (!f->reason.empty() && state_ == TrackingState::kConfirming) {
    // Not confirmed: the relocalisation is withdrawn and this frame is tried against the map.
    WithdrawRelocalisation();
    f->reason.clear();
  }
}

void System::TryRelocalise(FrameWork* f) {
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

void System::AcceptPose(FrameWork* f) {
  const TrackResult& result = f->result;
  const bool confirmed = state_ == TrackingState::kConfirming && !f->report.relocalised;
  if (confirmed) {
    stats_.relocalised.push_back(tentative_->evidence);
    tentative_.reset();
    ++stats_.relocalisations;
  }
  if (!f->report.relocalised) Transition(TrackingEvent::kTracked);
  f->confirmed = confirmed;
  if (suspended_) {
    ++stats_.frames;
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
  ++stats_.frames_tracked;
  frames_.push_back({f->t_ns, reference_->keyframe, result.frame_from_keyframe, 0.0, reference_->scale});
  if (pose_listener_ && !f->report.posed_before_wait) pose_listener_(f->index, *LastFramePose());
  stats_.tracking_ms.push_back(f->report.tracking_ms);
}

void System::HandToMappingSide(FrameWork* f) {
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
  job.relocalisations = stats_.relocalisations;
  job.readout = Readout();  // With the step to this frame: the mapping side's image is rectified.
  waits_.for_pending_keyframe = false;
  if (ShouldCreateKeyframe(scores, options_.keyframe) &&
      track_.quality.CheckKeyframeImage(f->signature.texture, f->previous_texture)) {
    if (mapping_thread_ && (mapping_thread_->KeyframesPending() > 0 || ReferenceIsStale())) {
      // Another keyframe is in flight, or was published while this frame was tracked against the
      // one before it: a keyframe made from this frame would hang off the older keyframe, next
      // to the newer one. The next frame waits for the pending keyframe (or not) and decides again.
      waits_.for_pending_keyframe = true;
    } else {
      job.keyframe = next_keyframe_++;
      // Its error model starts as the one fitted to its tracking residuals: it judges which map
      // points the keyframe sees before the PBA (System::SeenIn), which then refits it.
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
  if (job.keyframe < 0 && setup_.skip_traces_while_mapping && mapping_thread_ &&
      mapping_thread_->KeyframesPending() > 0) {
    ++stats_.traces_skipped;  // Its relocalisation count reaches the mapping side with the next job.
    return;
  }
  const auto t1 = std::chrono::steady_clock::now();
  Submit(std::move(job));
  if (!mapping_thread_) f->report.mapping_ms = MsSince(t1);
}

bool System::ReferenceIsStale() const {
  std::lock_guard<std::mutex> lock(reference_mutex_);
  return published_ != reference_;
}

void System::Submit(MappingJob job) {
  const int kf = job.keyframe;
  if (!mapping_thread_) {
    RunJob(job);
    if (kf >= 0) RunFinishJob(kf);
    return;
  }
  // A keyframe is done for the tracking side once its reference is published (the first job);
  // its candidates are selected after, while tracking goes on (the second, before any later job).
  if (kf < 0) {
    mapping_thread_->Submit([this, job = std::move(job)] { RunJob(job); }, false);
  } else {
    mapping_thread_->Submit([this, job = std::move(job)] { RunJob(job); }, true, [this, kf] { RunFinishJob(kf); });
  }
}

void System::RunFinishJob(int kf) {
  const auto t0 = std::chrono::steady_clock::now();
  FinishKeyframe(kf);
  stats_.mapping_ms.push_back(keyframe_ms_ + MsSince(t0));
}

void System::RunJob(const MappingJob& job) {
  const auto t0 = std::chrono::steady_clock::now();
  // A rolling shutter's frame is traced and mapped as the global shutter at its timestamp
  // would have seen it.
  const std::shared_ptr<const ImagePyramid> pyramid =
      job.readout.line_delay_s > 0.0 ? GlobalShutterPyramid(*job.pyramid, job.readout) : job.pyramid;
  TraceCandidates(*pyramid, job.reference, job.frame_from_reference, job.alpha, job.beta, job.exposure);
  stats_.tracing_ms.push_back(MsSince(t0));
  if (job.relocalisations > relocalisations_mapped_) {
    relocalisations_mapped_ = job.relocalisations;
    loop_ba_pending_ = true;
    seam_first_ = map_.NumKeyframes();
    rejoin_first_ = seam_first_;
  }
  if (job.keyframe < 0) return;
  // Tracking resumed against an older keyframe (relocalisation): it rejoins the temporal window,
  // with its points, so that the new keyframe is mapped against the part of the map it sees.
  if (std::find(window_.begin(), window_.end(), job.reference) == window_.end() &&
      std::find(covisible_.begin(), covisible_.end(), job.reference) == covisible_.end()) {
    window_.push_back(job.reference);
  }
  const Keyframe& ref = map_.keyframe(job.reference);
  CreateKeyframe(job.index, job.t_ns, pyramid, job.exposure, job.frame_from_reference * ref.cam_from_world,
                 FrameBrightness(ref, job.alpha, job.beta, job.exposure));
  const int kf = map_.NumKeyframes() - 1;
  DSM_CHECK(kf == job.keyframe, "keyframes were mapped out of order");
  map_.keyframe(kf).error_model = job.model;
  MapNewKeyframe(kf);
  stats_.per_keyframe.back().tracking_rmse = job.rmse;
  stats_.per_keyframe.back().tracking_inlier_ratio = job.inlier_ratio;
  keyframe_ms_ = MsSince(t0);
}

void System::UpdateReference(bool wait) {
  if (mapping_thread_ && wait) {
    ++stats_.keyframe_waits;
    mapping_thread_->WaitForKeyframes();
  }
  std::shared_ptr<const TrackingReference> next;
  {
    std::lock_guard<std::mutex> lock(reference_mutex_);
    next = published_;
  }
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

void System::Finish() {
  if (mapping_thread_) {
    mapping_thread_->WaitUntilIdle();
    // The run ended lost, with an adjustment stopped for a relocalisation: it ends now.
    mapping_thread_->Submit(
        [this] {
          if (RunParked()) PublishTrackingReference();
        },
        false);
    mapping_thread_->WaitUntilIdle();
    stats_.keyframe_queue_max = mapping_thread_->KeyframeQueueMax();
  }
  TrackInitFrames();  // When the run ended before the map matured.
  MergeInitTracked();
}

ReadoutTurn System::Readout() const {
  if (!(setup_.line_delay_s > 0.0 && frame_interval_ns_ > 0.0 && HasTrustedFrame())) return {};
  return {setup_.line_delay_s, track_.velocity.So3().Log() / (frame_interval_ns_ * 1e-9)};
}

std::shared_ptr<const ImagePyramid> System::GlobalShutterPyramid(const ImagePyramid& pyramid,
                                                                 const ReadoutTurn& turn) const {
  return std::make_shared<const ImagePyramid>(RectifyRotation(pyramid.ValuesLevel0(), camera_, turn),
                                              options_.pyramid_levels, /*gradients=*/false);
}

TrackResult System::TrackFrame(int index, const ImagePyramid& pyramid, double exposure) const {
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

void System::CommitPose(int index, const TrackResult& result, double exposure, std::optional<SE3d> velocity) {
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

void System::TraceCandidates(const ImagePyramid& pyramid, int reference, const SE3d& frame_from_reference,
                             double alpha, double beta, double exposure) {
  const Keyframe& ref = map_.keyframe(reference);
  const AffineBrightness frame = FrameBrightness(ref, alpha, beta, exposure);
  const SE3d frame_from_world = frame_from_reference * ref.cam_from_world;
  for (int h : window_) {
    auto it = candidates_.find(h);
    if (it == candidates_.end()) continue;
    const Keyframe& host = map_.keyframe(h);
    const SE3d frame_from_host = frame_from_world * host.cam_from_world.Inverse();
    Transfer tr;
    tr.s = static_cast<float>(BrightnessRatio(host.affine, frame, host.exposure, exposure));
    tr.b_host = static_cast<float>(host.affine.b);
    tr.b_frame = static_cast<float>(frame.b);
    // Each candidate is traced on its own: in parallel, with the result of a sequential loop.
    std::vector<Candidate>& candidates = it->second;
    tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t i) {
      Candidate& c = candidates[i];
      if (c.removed) return;
      const TraceStatus s = TraceCandidate(&c, pyramid, camera_, frame_from_host, tr, options_.epipolar);
      if (s == TraceStatus::kOutOfBounds || (s == TraceStatus::kOutlier && c.outlier_count >= 2)) c.removed = true;
    });
  }
}

Trajectory System::KeyframeTrajectory() const {
  // In time order: a merged map's keyframes follow this map's in ids (MergeVerified).
  std::vector<int> ids;
  for (int k = loaded_keyframes_; k < map_.NumKeyframes(); ++k) ids.push_back(k);
  std::stable_sort(ids.begin(), ids.end(), [&](int a, int b) { return map_.keyframe(a).t_ns < map_.keyframe(b).t_ns; });
  Trajectory t;
  for (int k : ids) t.Add(map_.keyframe(k).t_ns, map_.keyframe(k).WorldFromCam());
  return t;
}

double System::InitBaseline() const {
  return (map_.keyframe(1).cam_from_world.Inverse().Translation() -
          map_.keyframe(0).cam_from_world.Inverse().Translation())
      .norm();
}

Trajectory System::FrameTrajectory() const {
  Trajectory t;
  const double baseline = map_.NumKeyframes() > 1 ? InitBaseline() : 0.0;
  for (const FrameRecordInternal& f : frames_) {
    if (f.reference < 0) continue;
    SE3d frame_from_reference = f.frame_from_reference;
    if (f.init_baseline > 0.0)
      frame_from_reference.SetTranslation(frame_from_reference.Translation() * (baseline / f.init_baseline));
    frame_from_reference.SetTranslation(frame_from_reference.Translation() *
                                        (f.reference_scale / KeyframeScale(f.reference)));
    t.Add(f.t_ns, (frame_from_reference * map_.keyframe(f.reference).cam_from_world).Inverse());
  }
  return t;
}

int System::NumMapPoints() const { return map_.NumLivePoints(); }

std::shared_ptr<const MapSnapshot> System::TrackedMapSnapshot() const {
  return reference_ ? reference_->snapshot : nullptr;
}

std::optional<SE3d> System::LastFramePose() const {
  if (!reference_ || reference_->keyframe < 0) return std::nullopt;
  return WorldFromCam(track_.last_frame_from_reference);
}

SE3d System::WorldFromCam(const SE3d& frame_from_reference) const {
  // cam_from_world of the frame = frame_from_reference * reference's cam_from_world.
  return (frame_from_reference * reference_->cam_from_world[reference_->keyframe]).Inverse();
}

System::MapSize System::TrackedMapSize() const {
  if (!reference_) return {};
  return {static_cast<int>(reference_->cam_from_world.size()), reference_->map_points};
}

}  // namespace dsm
