// SPDX-License-Identifier: MIT
// Frame processing: initialisation and tracking. Keyframe mapping is in system_mapping.cc.
#include "dsm/system/system.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/image/noise.h"
#include "dsm/image/signature.h"
#include "dsm/system/mapping_thread.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/tracking/initializer.h"
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

System::System(const PinholeCamera& camera, const SystemOptions& options)
    : camera_(camera),
      options_(options),
      min_activation_distance_px_(options.activation.initial_min_distance_px),
      quality_(options.quality) {
  options_.Validate();
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
  if (options_.threaded) mapping_thread_ = std::make_unique<MappingThread>();
}

System::~System() = default;

void System::ChooseSmoothing(const Image<float>& first) {
  stats_.image_noise_sigma = EstimateNoiseSigma(first);
  if (options_.smoothing_sigma >= 0.0) {
    stats_.smoothing_sigma = options_.smoothing_sigma;
  } else {
    const bool noisy = stats_.image_noise_sigma >= options_.smoothing_noise_threshold;
    stats_.smoothing_sigma = noisy ? options_.smoothing_auto_sigma : 0.0;
  }
  options_.candidates.noise_gradient_gain = SmoothedGradientNoiseGain(static_cast<float>(stats_.smoothing_sigma));
}

FrameReport System::Process(int index, int64_t t_ns, const Image<float>& input, double exposure_ms,
                            std::optional<std::chrono::steady_clock::time_point> wait_until) {
  DSM_CHECK(input.width() == camera_.width && input.height() == camera_.height, "frame size differs from the camera");
  ++stats_.frames;
  const double exposure = exposure_ms > 0.0 ? exposure_ms : 1.0;
  if (stats_.smoothing_sigma < 0.0) ChooseSmoothing(input);
  const Image<float> smoothed =
      stats_.smoothing_sigma > 0.0 ? GaussianSmooth(input, static_cast<float>(stats_.smoothing_sigma)) : Image<float>();
  const Image<float>& image = stats_.smoothing_sigma > 0.0 ? smoothed : input;
  if (!reference_) return Initialize(index, t_ns, image, exposure);

  // After a relocalisation the reference is an older keyframe: even a live camera waits for the
  // keyframe made from the confirming frame, or tracking would drift off the old one meanwhile.
  const auto wait_start = std::chrono::steady_clock::now();
  const bool wait = (want_keyframe_ && options_.wait_for_mapping) || wait_after_relocalisation_;
  if (!wait && wait_until && mapping_thread_ && mapping_thread_->KeyframesPending() > 0) {
    // A frame tracked against the keyframe before the pending one lands further from its
    // reference, and its candidates' traces and the next keyframe with it: as long as the next
    // frame is not due, it waits.
    ++stats_.keyframe_waits;
    if (!mapping_thread_->WaitForKeyframesUntil(*wait_until)) ++stats_.keyframe_wait_timeouts;
  }
  UpdateReference(wait);
  wait_after_relocalisation_ = false;
  auto t0 = std::chrono::steady_clock::now();
  FrameReport report;
  report.index = index;
  report.wait_ms = std::chrono::duration<double, std::milli>(t0 - wait_start).count();
  auto pyramid = std::make_shared<const ImagePyramid>(image, options_.pyramid_levels, /*gradients=*/false);
  // The quality test (tracking_quality.h): the image first, then the alignment. While lost, every
  // frame with texture enough is tried against the map (Relocalise). A relocalisation is tentative
  // until the next frame, tracked from it, passes the test as well; otherwise it is withdrawn and
  // that frame is tried against the map in turn.
  const FrameSignature signature = ComputeSignature(*pyramid);
  const double previous_texture = previous_texture_;
  previous_texture_ = signature.texture;
  std::string reason = quality_.CheckImage(signature.texture);
  TrackResult result;
  if (reason.empty() && !lost_) {
    result = TrackFrame(*pyramid, exposure);
    reason = quality_.CheckTracking(result, result.frame_from_keyframe * last_frame_from_reference_.Inverse(), 1,
                                    tracker_->MeanIdepth());
    if (!reason.empty() && mapping_thread_ && mapping_thread_->KeyframesPending() > 0) {
      // Failed against the keyframe before the one being mapped (a wait that ended first): the
      // newer keyframe may see what the camera sees now. Waiting for it costs this frame some
      // latency; a lost frame would cost a relocalisation, which waits for the mapping side too.
      ++stats_.keyframe_retracks;
      const auto retrack_start = std::chrono::steady_clock::now();
      mapping_thread_->WaitForKeyframes();
      UpdateReference(false);
      t0 += std::chrono::steady_clock::now() - retrack_start;
      report.wait_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - retrack_start).count();
      result = TrackFrame(*pyramid, exposure);
      reason = quality_.CheckTracking(result, result.frame_from_keyframe * last_frame_from_reference_.Inverse(), 1,
                                      tracker_->MeanIdepth());
    }
    if (!reason.empty() && tentative_) {
      WithdrawRelocalisation();
      reason.clear();
    }
  }
  if (reason.empty() && lost_) {
    // Only a frame with the usual texture may re-anchor the camera: half of it hidden by a hand
    // sliding off the lens, any pose fits the rest as well as the right one.
    reason = quality_.CheckRelocalisationImage(signature.texture);
    if (reason.empty()) {
      Tentative before = SaveTentative(index);
      report.relocalised = Relocalise(*pyramid, signature, exposure, &result, &reason);
      if (report.relocalised) tentative_ = std::move(before);
    }
    if (!report.relocalised) ++failed_relocalisations_;
  }
  if (!reason.empty() && tentative_) WithdrawRelocalisation();
  report.tracking_ms = MsSince(t0);
  if (!reason.empty()) return LostFrame(std::move(report), t_ns, std::move(reason));
  const bool confirmed = tentative_ && !report.relocalised;
  if (confirmed) {
    tentative_.reset();
    ++stats_.relocalisations;
  }
  lost_ = false;
  lost_in_a_row_ = failed_relocalisations_ = 0;
  CommitPose(result, exposure, /*keep_velocity=*/!report.relocalised);
  if (report.relocalised) {
    quality_.Restart(result.residual_p50, signature.texture);
  } else {
    quality_.Trust(result.residual_p50, signature.texture);
  }
  last_frame_keyframe_ = -1;
  report.status = TrackingStatus::kOk;
  ++stats_.frames_tracked;
  frames_.push_back({t_ns, reference_->keyframe, result.frame_from_keyframe});
  stats_.tracking_ms.push_back(report.tracking_ms);
  // A tentative pose feeds nothing to the mapping side (and never makes a keyframe).
  if (report.relocalised) return report;

  if (first_rmse_after_keyframe_ == 0.0) first_rmse_after_keyframe_ = result.rmse;
  KeyframeScores scores;
  scores.parallax = result.frame_from_keyframe.Translation().norm() * tracker_->MeanIdepth();
  scores.visibility = result.visibility;
  scores.brightness = std::abs(result.alpha - std::log(exposure / reference_->exposure[reference_->keyframe]));
  scores.rmse = result.rmse;
  scores.first_rmse = first_rmse_after_keyframe_;

  MappingJob job;
  job.index = index;
  job.t_ns = t_ns;
  job.exposure = exposure;
  job.pyramid = std::move(pyramid);
  job.reference = reference_->keyframe;
  job.frame_from_reference = result.frame_from_keyframe;
  job.alpha = result.alpha;
  job.beta = result.beta;
  want_keyframe_ = false;
  if (ShouldCreateKeyframe(scores, options_.keyframe) && quality_.CheckKeyframeImage(signature.texture, previous_texture)) {
    if (mapping_thread_ && (mapping_thread_->KeyframesPending() > 0 || ReferenceIsStale())) {
      // Another keyframe is in flight, or was published while this frame was tracked against the
      // one before it: a keyframe made from this frame would hang off the older keyframe, next
      // to the newer one.
      want_keyframe_ = true;  // The next frame waits for the pending keyframe (or not) and decides again.
    } else {
      job.keyframe = next_keyframe_++;
      // Its error model starts as the one fitted to its tracking residuals: it judges which map
      // points the keyframe sees before the PBA (System::SeenIn), which then refits it.
      job.model = options_.tracker.robust.kind == options_.pba.robust.kind ? result.model
                                                                           : DefaultErrorModel(options_.pba.robust);
      job.rmse = result.rmse;
      job.inlier_ratio = result.inlier_ratio;
      frames_.back() = {t_ns, job.keyframe, SE3d()};
      last_frame_keyframe_ = job.keyframe;
      report.keyframe = true;
      wait_after_relocalisation_ = confirmed;
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  Submit(std::move(job));
  if (!mapping_thread_) report.mapping_ms = MsSince(t1);
  return report;
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
  mapping_thread_->Submit([this, job = std::move(job)] { RunJob(job); }, kf >= 0);
  if (kf >= 0) mapping_thread_->Submit([this, kf] { RunFinishJob(kf); }, false);
}

void System::RunFinishJob(int kf) {
  const auto t0 = std::chrono::steady_clock::now();
  FinishKeyframe(kf);
  stats_.mapping_ms.push_back(keyframe_ms_ + MsSince(t0));
}

void System::RunJob(const MappingJob& job) {
  const auto t0 = std::chrono::steady_clock::now();
  TraceCandidates(*job.pyramid, job.reference, job.frame_from_reference, job.alpha, job.beta, job.exposure);
  stats_.tracing_ms.push_back(MsSince(t0));
  if (job.keyframe < 0) return;
  // Tracking resumed against an older keyframe (relocalisation): it rejoins the temporal window,
  // with its points, so that the new keyframe is mapped against the part of the map it sees.
  if (std::find(window_.begin(), window_.end(), job.reference) == window_.end() &&
      std::find(covisible_.begin(), covisible_.end(), job.reference) == covisible_.end()) {
    window_.push_back(job.reference);
  }
  const Keyframe& ref = map_.keyframe(job.reference);
  CreateKeyframe(job.index, job.t_ns, job.pyramid, job.exposure, job.frame_from_reference * ref.cam_from_world,
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
    last_frame_from_reference_ = last_frame_from_reference_ * next->cam_from_world[o] * next->cam_from_world[n].Inverse();
    // Absolute brightness of the last frame, then relative to the new reference.
    const AffineBrightness f = FrameBrightness(next->affine[o], next->exposure[o], last_alpha_, last_beta_, last_exposure_);
    internal::RelativeBrightness(f, last_exposure_, next->affine[n], next->exposure[n], &last_alpha_, &last_beta_);
  } else {
    // The new reference is the keyframe made from the last tracked frame.
    last_frame_from_reference_ = SE3d();
    last_alpha_ = 0.0;
    last_beta_ = 0.0;
  }
  reference_ = std::move(next);
  tracker_->SetReference(reference_->pyramid.get(), camera_, reference_->points);
  first_rmse_after_keyframe_ = 0.0;
}

void System::Finish() {
  if (mapping_thread_) {
    mapping_thread_->WaitUntilIdle();
    stats_.keyframe_queue_max = mapping_thread_->KeyframeQueueMax();
  }
  TrackInitFrames();  // When the run ended before the map matured.
  MergeInitTracked();
}

FrameReport System::Initialize(int index, int64_t t_ns, const Image<float>& image, double exposure) {
  FrameReport report;
  report.index = index;
  report.status = TrackingStatus::kInitializing;
  const auto t0 = std::chrono::steady_clock::now();
  PendingFrame frame{index, t_ns, exposure, std::make_shared<const ImagePyramid>(image, options_.pyramid_levels)};
  if (!initializer_->HasReference() || static_cast<int>(pending_.size()) >= options_.max_initialization_frames) {
    // (Re)start on this frame; frames waiting on an older reference stay untracked.
    for (const PendingFrame& p : pending_) frames_.push_back({p.t_ns, -1, SE3d()});
    pending_.clear();
    initializer_->SetReference(image, camera_);
    pending_.push_back(std::move(frame));
    report.reason = "waiting for motion";
    return report;
  }
  const InitResult init = initializer_->AddFrame(image);
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
  stats_.initialization = init.planar ? "planar" : "two-view";
  PendingFrame& first = pending_.front();
  PendingFrame& last = pending_.back();
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
    if (!SampleHostPatch(map_.keyframe(0).Pyramid(), 0, p.pixel, &patch)) continue;
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
  want_keyframe_ = true;
  next_keyframe_ = 2;
  last_frame_keyframe_ = 1;
  UpdateReference(false);
  stats_.frames_tracked += 2;

  const int k = static_cast<int>(pending_.size()) - 1;
  const SE3d kf1_from_kf0 = init.current_from_reference;
  std::vector<PendingFrame> between(pending_.begin() + 1, pending_.begin() + std::max(1, k));
  for (const PendingFrame& p : between) frames_.push_back({p.t_ns, -1, SE3d()});
  // Tracked once the first bundle adjustments have settled the young map (FinishKeyframe).
  init_between_ = {std::move(between), kf1_from_kf0, k};
  frames_.push_back({last.t_ns, 1, SE3d()});
  std::stable_sort(frames_.begin(), frames_.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  velocity_ = k > 0 ? Scale(kf1_from_kf0, 1.0 / k) : SE3d();
  last_exposure_ = last.exposure;
  pending_.clear();
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
      std::optional<TrackResult> r = tracker.Track(*between[i].pyramid, step * previous, 0.0, 0.0);
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

TrackResult System::TrackFrame(const ImagePyramid& pyramid, double exposure) const {
  // Relative brightness guess: the last one, corrected for the change of exposure time.
  const double alpha_guess = last_alpha_ + std::log(exposure / last_exposure_);
  // Guesses of frame_from_reference: constant velocity first, then alternatives.
  const SE3d last = last_frame_from_reference_;
  std::vector<SE3d> guesses = {velocity_ * last, last, velocity_ * velocity_ * last, Scale(velocity_, 0.5) * last};
  for (double angle : {0.02, -0.02})
    for (int axis = 0; axis < 3; ++axis) guesses.push_back(internal::RotationAbout(axis, angle) * velocity_ * last);
  std::vector<std::pair<double, int>> ranked;
  for (size_t g = 0; g < guesses.size(); ++g)
    ranked.emplace_back(tracker_->CoarseEnergy(pyramid, guesses[g], alpha_guess, last_beta_), static_cast<int>(g));
  // Constant velocity stays first unless another guess is clearly better.
  std::stable_sort(ranked.begin() + 1, ranked.end());
  if (ranked[1].first < 0.7 * ranked[0].first) std::swap(ranked[0], ranked[1]);
  TrackResult best;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const TrackResult r = tracker_->Track(pyramid, guesses[ranked[attempt].second], alpha_guess, last_beta_);
    if (r.ok && (!best.ok || r.rmse < best.rmse)) best = r;
    if (!best.ok && attempt == 0) best = r;
    // Other guesses only when this one failed or left a much larger residual than usual.
    if (best.ok && (first_rmse_after_keyframe_ == 0.0 || best.rmse < 2.0 * first_rmse_after_keyframe_)) break;
  }
  return best;
}

void System::CommitPose(const TrackResult& result, double exposure, bool keep_velocity) {
  velocity_ = keep_velocity ? result.frame_from_keyframe * last_frame_from_reference_.Inverse() : SE3d();
  last_frame_from_reference_ = result.frame_from_keyframe;
  last_alpha_ = result.alpha;
  last_beta_ = result.beta;
  last_exposure_ = exposure;
}

FrameReport System::LostFrame(FrameReport report, int64_t t_ns, std::string reason) {
  report.status = TrackingStatus::kLost;
  report.reason = std::move(reason);
  frames_.push_back({t_ns, -1, SE3d()});
  ++stats_.frames_lost;
  ++lost_in_a_row_;
  if (!lost_) {
    lost_ = true;
    stats_.lost_episodes.push_back({report.index, report.index});
  }
  stats_.lost_episodes.back().second = report.index;
  return report;
}

System::Tentative System::SaveTentative(int index) const {
  Tentative t;
  t.index = index;
  t.record = frames_.size();
  t.reference = reference_;
  t.last_frame_from_reference = last_frame_from_reference_;
  t.velocity = velocity_;
  t.alpha = last_alpha_;
  t.beta = last_beta_;
  t.exposure = last_exposure_;
  t.first_rmse_after_keyframe = first_rmse_after_keyframe_;
  t.quality = quality_;
  t.lost_in_a_row = lost_in_a_row_;
  t.failed_relocalisations = failed_relocalisations_;
  return t;
}

void System::WithdrawRelocalisation() {
  Tentative& t = *tentative_;
  // The relocalised frame becomes a lost one of the same episode.
  frames_[t.record].reference = -1;
  --stats_.frames_tracked;
  ++stats_.frames_lost;
  stats_.lost_episodes.back().second = t.index;
  lost_in_a_row_ = t.lost_in_a_row + 1;
  failed_relocalisations_ = t.failed_relocalisations + 1;
  // The mapping side is idle: it was handed nothing since the camera was lost.
  if (reference_ != t.reference) AdoptReference(t.reference);
  last_frame_from_reference_ = t.last_frame_from_reference;
  velocity_ = t.velocity;
  last_alpha_ = t.alpha;
  last_beta_ = t.beta;
  last_exposure_ = t.exposure;
  first_rmse_after_keyframe_ = t.first_rmse_after_keyframe;
  quality_ = t.quality;
  lost_ = true;
  tentative_.reset();
}

bool System::NeedsNewMap() const {
  return options_.relocalisation.max_lost_frames > 0 && failed_relocalisations_ >= options_.relocalisation.max_lost_frames;
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
  Trajectory t;
  for (int k = 0; k < map_.NumKeyframes(); ++k) t.Add(map_.keyframe(k).t_ns, map_.keyframe(k).WorldFromCam());
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
  // cam_from_world of the frame = frame_from_reference * reference's cam_from_world.
  return (last_frame_from_reference_ * reference_->cam_from_world[reference_->keyframe]).Inverse();
}

System::MapSize System::TrackedMapSize() const {
  if (!reference_) return {};
  return {static_cast<int>(reference_->cam_from_world.size()), reference_->map_points};
}

}  // namespace dsm
