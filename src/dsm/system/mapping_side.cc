// SPDX-License-Identifier: MIT
// The mapping side's work on each tracked frame and keyframe: candidate tracing, observations,
// window, activation, bundle adjustment, point culling, candidates, the tracking reference.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/mapping/activation.h"
#include "dsm/mapping/candidate_selector.h"
#include "dsm/mapping/covisibility.h"
#include "dsm/mapping/observation_check.h"
#include "dsm/mapping/occlusion.h"
#include "dsm/mapping/projection.h"
#include "dsm/mapping/window.h"
#include "dsm/optimization/pba.h"
#include "dsm/system/mapping_thread.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

using internal::MsSince;

AffineBrightness FrameBrightness(const Keyframe& ref, double alpha, double beta, double exposure) {
  return internal::FrameBrightness(ref.affine, ref.exposure, alpha, beta, exposure);
}

// The level-0 distance map of keyframe `target` with the projections of the points `ids`.
DistanceMap ProjectedDistanceMap(const Map& map, const PinholeCamera& camera, const std::vector<int>& ids, int target) {
  DistanceMap distance(camera.width, camera.height);
  for (int pid : ids) {
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map, camera, map.point(pid), target, 0.f, &px, &rho)) distance.Add(px);
  }
  return distance;
}

}  // namespace

MappingSide::MappingSide(const PinholeCamera& camera, const SystemOptions& options, const SystemSetup& setup,
                         MappingStats* stats)
    : camera_(camera),
      options_(options),
      setup_(setup),
      stats_(stats),
      min_activation_distance_px_(options.activation.initial_min_distance_px),
      places_(&own_places_) {
  places_->Join(this);
  if (options_.loop_closure.enabled && options_.mode == MapMode::kFull) {
    if (options_.loop_closure.vocabulary.empty()) {
      loop_.vocabulary = &Vocabulary::BuiltIn();
    } else {
      loop_.own_vocabulary = std::make_unique<Vocabulary>(Vocabulary::Read(options_.loop_closure.vocabulary));
      loop_.vocabulary = loop_.own_vocabulary.get();
    }
  }
}

MappingSide::~MappingSide() { places_->Leave(this); }

void MappingSide::UsePlaces(AtlasPlaces* places) {
  DSM_CHECK(map_.NumKeyframes() == 0, "a map joins a place index before it has keyframes");
  places_->Leave(this);
  places_ = places;
  places_->Join(this);
}

void MappingSide::ChooseNoiseHandling(double noise_sigma) {
  stats_->image_noise_sigma = noise_sigma;
  if (stats_->image_noise_sigma < options_.candidates.contrast_min_noise) options_.candidates.contrast_factor = 0.f;
  stats_->contrast_floor = options_.candidates.contrast_factor > 0.f;
  bool bspline = options_.interpolation == "bspline" ||
                 (options_.interpolation == "auto" && stats_->image_noise_sigma >= options_.bspline_min_noise);
  // A loaded map's points were sampled its way: it keeps it.
  if (map_.NumPoints() > 0) bspline = map_.interpolation() == Interpolation::kBSpline;
  if (map_.NumPoints() == 0) map_.set_interpolation(bspline ? Interpolation::kBSpline : Interpolation::kBilinear);
  stats_->interpolation = bspline ? "bspline" : "bilinear";
  TextureLossOptions& texture = options_.pba.texture_loss;
  if (options_.mode == MapMode::kFull && options_.texture_loss_min_noise > 0.0 &&
      stats_->image_noise_sigma >= options_.texture_loss_min_noise)
    texture.max_variance_ratio = kTextureLossRatio;
  stats_->texture_loss = texture.max_variance_ratio > 0.0;
}

void MappingSide::RunFinishJob(int kf) {
  const auto t0 = std::chrono::steady_clock::now();
  FinishKeyframe(kf);
  stats_->mapping_ms.push_back(keyframe_ms_ + MsSince(t0));
}

void MappingSide::RunJob(const MappingJob& job) {
  const auto t0 = std::chrono::steady_clock::now();
  // A rolling shutter's frame is traced and mapped as the global shutter at its timestamp
  // would have seen it.
  const std::shared_ptr<const ImagePyramid> pyramid =
      job.readout.line_delay_s > 0.0 ? internal::GlobalShutterPyramid(*job.pyramid, camera_, job.readout, options_.pyramid_levels) : job.pyramid;
  TraceCandidates(*pyramid, job.reference, job.frame_from_reference, job.alpha, job.beta, job.exposure);
  stats_->tracing_ms.push_back(MsSince(t0));
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
  stats_->per_keyframe.back().tracking_rmse = job.rmse;
  stats_->per_keyframe.back().tracking_inlier_ratio = job.inlier_ratio;
  keyframe_ms_ = MsSince(t0);
}

void MappingSide::TraceCandidates(const ImagePyramid& pyramid, int reference, const SE3d& frame_from_reference,
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

Trajectory MappingSide::KeyframeTrajectory() const {
  // In time order: a merged map's keyframes follow this map's in ids (MergeVerified).
  std::vector<int> ids;
  for (int k = loaded_keyframes_; k < map_.NumKeyframes(); ++k) ids.push_back(k);
  std::stable_sort(ids.begin(), ids.end(), [&](int a, int b) { return map_.keyframe(a).t_ns < map_.keyframe(b).t_ns; });
  Trajectory t;
  for (int k : ids) t.Add(map_.keyframe(k).t_ns, map_.keyframe(k).WorldFromCam());
  return t;
}

double MappingSide::InitBaseline() const {
  if (map_.NumKeyframes() < 2) return 0.0;
  return (map_.keyframe(1).cam_from_world.Inverse().Translation() -
          map_.keyframe(0).cam_from_world.Inverse().Translation())
      .norm();
}

void MappingSide::CreateKeyframe(int index, int64_t t_ns, std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                            const SE3d& cam_from_world, const AffineBrightness& affine) {
  auto kf = std::make_unique<Keyframe>();
  kf->frame_index = index;
  kf->t_ns = t_ns;
  kf->cam_from_world = cam_from_world;
  kf->affine = affine;
  kf->exposure = exposure;
  // A tracked frame's pyramid holds intensities only; a keyframe's needs the gradients.
  kf->pyramid = pyramid->HasGradients() ? std::move(pyramid)
                                        : std::make_shared<const ImagePyramid>(pyramid->WithGradients());
  kf->error_model = DefaultErrorModel(options_.pba.robust);
  kf->signature = ComputeSignature(*kf->pyramid);
  map_.AddKeyframe(std::move(kf));
  ++stats_->keyframes;
}

std::vector<int> MappingSide::ActiveKeyframes() const {
  std::vector<int> active = window_;
  active.insert(active.end(), covisible_.begin(), covisible_.end());
  return active;
}

std::vector<int> MappingSide::ActivePointIds() const {
  std::vector<int> ids;
  for (int kf : ActiveKeyframes())
    for (int pid : map_.keyframe(kf).points)
      if (!map_.point(pid).removed) ids.push_back(pid);
  return ids;
}

void MappingSide::MapNewKeyframe(int kf) {
  stats_->per_keyframe.push_back({map_.keyframe(kf).frame_index, 0, 0, {}});
  map_.LoadPyramids(window_);
  // Observations of the temporal window's points in the new keyframe, unless a nearer part of the
  // map hides them there (the PBA verifies the rest).
  OcclusionGrid occlusion(camera_.width, camera_.height, options_.occlusion);
  AddToOcclusionGrid(window_, kf, &occlusion);
  for (int h : window_)
    for (int pid : map_.keyframe(h).points) {
      Point& p = map_.point(pid);
      Eigen::Vector2f px;
      float rho;
      if (!p.removed && ProjectPoint(map_, camera_, p, kf, 4.f, &px, &rho) && !occlusion.IsOccluded(px, rho))
        p.observations.push_back({kf, false});
    }
  window_.push_back(kf);
  const bool culling = options_.keyframe_culling && options_.mode == MapMode::kFull && !localizing_;
  for (int drop; (drop = SelectKeyframeToDrop(map_, window_, options_.window)) >= 0;) {
    window_.erase(std::find(window_.begin(), window_.end(), drop));
    candidates_.erase(drop);
    if (culling) cull_pending_.push_back(drop);  // Judged once the window's adjustment lets it go.
  }
  SelectCovisible(kf, &occlusion);
  ActivateCandidates(kf);
  // Covisible keyframes bring their points; their poses stay where the older map put them unless
  // asked otherwise (moving them cost accuracy on every synthetic scene).
  const std::vector<int> held = options_.window.optimize_covisible_poses ? std::vector<int>{} : covisible_;
  const PbaSummary pba = RunPba(&map_, camera_, ActiveKeyframes(), options_.pba, HeldWithLoaded(held));
  MappingStats::KeyframeLog& log = stats_->per_keyframe.back();
  log.pba_keyframes = pba.keyframes;
  log.pba_fixed_keyframes = pba.fixed_keyframes;
  log.pba_points = pba.points;
  log.pba_observations = pba.observations;
  log.pba_iterations = pba.iterations;
  log.pba_ms = pba.time_ms;
  log.observations_removed = pba.observations_removed;
  log.observations_texture_lost = pba.observations_texture_lost;
  stats_->pba_ms.push_back(pba.time_ms);
  log.points_culled = CullPoints();
  // What the keyframe sees after its adjustment: the window's points hosted or observed (inlier)
  // in it, and of those the covisible keyframes' (the map before the temporal window).
  for (int pid : ActivePointIds()) {
    const Point& p = map_.point(pid);
    const Observation* o = p.host == kf ? nullptr : p.FindObservation(kf);
    if (p.host != kf && (o == nullptr || o->outlier)) continue;
    ++log.points_seen;
    if (std::find(covisible_.begin(), covisible_.end(), p.host) != covisible_.end()) ++log.old_points_seen;
  }
  CullUnusedKeyframes(pba.cameras);
  if (localizing_) RetireTemporaries(kf);
  PublishTrackingReference();
}

void MappingSide::FinishKeyframe(int kf) {
  SelectCandidates(kf);
  if (kf == kInitTrackingKeyframe) TrackInitFrames();
  // The young map's and the loop adjustments after publication (in the two-thread paces tracking
  // goes on against the new keyframe meanwhile), then the keyframe published again, adjusted
  // (UpdateReference keeps the frames' poses relative to it).
  bool adjusted = RunParked();
  if (AdjustYoungMap()) adjusted = true;
  if (RejoinAfterRelocalisation(kf)) adjusted = true;
  if (AdjustSeam(kf)) adjusted = true;
  if (AdjustMerge(kf)) {
    adjusted = true;
  } else if (AdjustLoop(kf)) {
    adjusted = true;
  }
  if (DetectAndCloseLoop(kf)) adjusted = true;
  if (adjusted) PublishTrackingReference();
  if (setup_.keyframe_features && thread_) KeyframeFeatures(kf);
  // Keyframes keep their pyramids while a recent mapping step used them.
  map_.ReleaseUnusedPyramids(options_.keep_pyramid_keyframes);
  stats_->pyramids_loaded_max = std::max(stats_->pyramids_loaded_max, map_.NumLoadedPyramids());
  stats_->pyramids_rebuilt = map_.NumPyramidsRebuilt();
}

void MappingSide::AddToOcclusionGrid(const std::vector<int>& keyframes, int target, OcclusionGrid* grid) const {
  for (int h : keyframes)
    for (int pid : map_.keyframe(h).points) {
      const Point& p = map_.point(pid);
      Eigen::Vector2f px;
      float rho;
      if (!p.removed && ProjectPoint(map_, camera_, p, target, 0.f, &px, &rho)) grid->Add(px, rho);
    }
}

void MappingSide::SelectCovisible(int newest, OcclusionGrid* occlusion) {
  covisible_.clear();
  if (options_.mode != MapMode::kFull) return;
  DistanceMap distance = ProjectedDistanceMap(map_, camera_, ActivePointIds(), newest);
  MappingStats::KeyframeLog& log = stats_->per_keyframe.back();
  CovisibleSelection selection = SelectCovisibleKeyframes(map_, camera_, window_, options_.window, &distance);
  // Old points cover the newest keyframe's view where they are visible in it.
  old_pixels_.clear();
  const std::vector<uint8_t> old_seen = SeenIn(selection.other_old_points, newest);
  for (size_t i = 0; i < old_seen.size(); ++i)
    if (old_seen[i]) old_pixels_.push_back(selection.other_old_pixels[i]);
  for (const CovisibleChoice& c : selection.chosen) covisible_.push_back(c.keyframe);
  log.covisible = covisible_;
  AddToOcclusionGrid(covisible_, newest, occlusion);
  for (int h : covisible_) {
    // Re-observations: the covisible keyframe's points seen by the new keyframe from a similar angle.
    for (int pid : map_.keyframe(h).points) {
      Point& p = map_.point(pid);
      Eigen::Vector2f px;
      float rho;
      if (p.removed || p.FindObservation(newest) != nullptr || !ProjectPoint(map_, camera_, p, newest, 4.f, &px, &rho) ||
          ViewAngleDeg(map_, camera_, p, newest) > options_.window.max_view_angle_deg ||
          occlusion->IsOccluded(px, rho))
        continue;
      p.observations.push_back({newest, false});
      ++log.reobservations;
    }
  }
  stats_->covisible_keyframes_selected += static_cast<int>(covisible_.size());
  stats_->reobservations += log.reobservations;
}

std::vector<uint8_t> MappingSide::SeenIn(const std::vector<int>& ids, int target) {
  map_.LoadPyramids({target});  // The hosts' side is the points' own patch.
  const Keyframe& keyframe = map_.keyframe(target);
  std::vector<uint8_t> seen(ids.size(), 0);
  tbb::parallel_for(size_t{0}, ids.size(), [&](size_t i) {
    const Point& p = map_.point(ids[i]);
    Eigen::Vector2f px;
    float rho;
    seen[i] = p.host == target || (ProjectPoint(map_, camera_, p, target, 0.f, &px, &rho) &&
                                   LooksConsistent(map_, camera_, p, target, keyframe.error_model,
                                                   options_.pba.drop_outlier_ratio));
  });
  return seen;
}

void MappingSide::ActivateCandidates(int newest) {
  const std::vector<int> active = ActivePointIds();
  // Only points seen in the newest keyframe cover its image: one hidden behind a new occluder
  // would keep the occluder from getting points of its own.
  const std::vector<uint8_t> seen = SeenIn(active, newest);
  std::vector<int> visible;
  for (size_t i = 0; i < active.size(); ++i)
    if (seen[i]) visible.push_back(active[i]);
  DistanceMap distance = ProjectedDistanceMap(map_, camera_, visible, newest);
  // Places the older map already covers (points of old keyframes outside the window, seen at a
  // similar scale and angle) get no new points: the map is re-used, not duplicated.
  for (const Eigen::Vector2f& px : old_pixels_) distance.Add(px);
  // Keep the window near its target number of points by adapting the spacing; it only shrinks
  // when the newest keyframe's view is not already covered by points it sees (the window's and
  // the older map's). Points out of view or hidden cover nothing: counting them would leave the
  // view of a camera circling past near objects thinly covered, and its scale lost.
  const int target = options_.activation.target_points;
  const int num_active = static_cast<int>(active.size());
  const int covered = static_cast<int>(visible.size() + old_pixels_.size());
  if (covered < 0.8 * target) min_activation_distance_px_ = std::max(2.f, min_activation_distance_px_ - 1.f);
  if (num_active > 1.2 * target) min_activation_distance_px_ += 1.f;

  for (int h : window_) {
    if (h == newest) continue;
    auto it = candidates_.find(h);
    if (it == candidates_.end()) continue;
    std::vector<int> targets;
    for (int k : window_)
      if (k != h) targets.push_back(k);
    for (Candidate& c : it->second) {
      if (c.removed || c.status != TraceStatus::kGood || c.pixel_interval > options_.activation.max_pixel_interval ||
          c.quality < options_.activation.min_quality)
        continue;
      Point probe;
      probe.host = h;
      probe.pixel = c.pixel;
      probe.idepth = c.Idepth();
      Eigen::Vector2f px;
      float rho;
      if (!ProjectPoint(map_, camera_, probe, newest, 4.f, &px, &rho)) continue;
      if (distance.Distance(px) < min_activation_distance_px_) continue;
      RefinedPoint refined;
      c.removed = true;  // Activated or rejected: it leaves the candidates either way.
      if (!RefineCandidate(map_, camera_, h, c, targets, options_.activation, &refined)) continue;
      probe.idepth = refined.idepth;
      probe.created_at_keyframe = map_.NumKeyframes();
      for (int t : refined.targets) probe.observations.push_back({t, false});
      map_.AddPoint(probe);
      ++stats_->points_created;
      ++stats_->per_keyframe.back().points_created;
      if (ProjectPoint(map_, camera_, probe, newest, 0.f, &px, &rho)) distance.Add(px);
    }
  }
}

int MappingSide::CullPoints() {
  const int num_keyframes = map_.NumKeyframes();
  int culled = 0;
  for (int pid : ActivePointIds()) {
    Point& p = map_.point(pid);
    if (map_.keyframe(p.host).frozen) continue;
    const int age = num_keyframes - p.created_at_keyframe;  // Keyframes created since activation.
    if (age < 2) {
      // Young: must be seen in every window keyframe created since.
      for (int k : window_) {
        if (k == p.host || k < p.created_at_keyframe - 1) continue;
        const Observation* o = p.FindObservation(k);
        if (o == nullptr || o->outlier) {
          p.removed = true;
          break;
        }
      }
    } else if (p.NumGoodObservations() + 1 < 3) {
      p.removed = true;  // Mature points need three keyframes (host included).
    }
    culled += p.removed;
  }
  return culled;
}

void MappingSide::SelectCandidates(int kf) {
  std::vector<Candidate>& list = candidates_[kf];
  list.clear();
  const Keyframe& keyframe = map_.keyframe(kf);
  for (const SelectedPixel& s : dsm::SelectCandidates(keyframe.Pyramid(), options_.candidates)) {
    Candidate c;
    if (MakeCandidate(keyframe.Pyramid(), s.pixel, &c)) list.push_back(c);
  }
}

std::vector<ReferencePoint> MappingSide::PointsSeenIn(int kf) {
  std::vector<int> ids;
  for (int pid = 0; pid < map_.NumPoints(); ++pid) {
    const Point& p = map_.point(pid);
    if (p.removed) continue;
    const Observation* o = p.host == kf ? nullptr : p.FindObservation(kf);
    if (p.host == kf || (o != nullptr && !o->outlier)) ids.push_back(pid);
  }
  return ReferencePointsIn(kf, ids);
}

std::vector<ReferencePoint> MappingSide::ReferencePointsIn(int kf, const std::vector<int>& ids, bool adjusted) {
  std::vector<ReferencePoint> points;
  const bool verified = adjusted && options_.tracker.verified_reference;
  for (int pid : ids) {
    Point& p = map_.point(pid);
    // Only points the bundle adjustment saw in the keyframe (TrackerOptions).
    const Observation* o = p.FindObservation(kf);
    if (verified && p.host != kf && (o == nullptr || o->outlier)) continue;
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map_, camera_, p, kf, 2.f, &px, &rho)) points.push_back({px, rho});
  }
  return points;
}

void MappingSide::PublishTrackingReference() {
  const int newest = window_.back();
  PublishReference(newest, ReferencePointsIn(newest, ActivePointIds()));
}

std::shared_ptr<const TrackingReference> MappingSide::MakeReference(
    int kf, std::vector<ReferencePoint> points, std::shared_ptr<const ImagePyramid> pyramid) const {
  auto ref = std::make_shared<TrackingReference>();
  ref->points = std::move(points);
  ref->keyframe = kf;
  ref->pyramid = pyramid ? std::move(pyramid) : map_.keyframe(kf).pyramid;
  for (int k = 0; k < map_.NumKeyframes(); ++k) {
    ref->cam_from_world.push_back(map_.keyframe(k).cam_from_world);
    ref->affine.push_back(map_.keyframe(k).affine);
    ref->exposure.push_back(map_.keyframe(k).exposure);
  }
  ref->map_points = map_.NumLivePoints();
  ref->texture = map_.keyframe(kf).signature.texture;
  ref->scale = KeyframeScale(kf);
  if (setup_.map_snapshots) {
    auto snapshot = std::make_shared<MapSnapshot>();
    snapshot->points = LivePoints(map_, camera_);
    for (int k = 0; k < map_.NumKeyframes(); ++k) {
      snapshot->world_from_cam.push_back(map_.keyframe(k).WorldFromCam());
      snapshot->keyframe_frames.push_back(map_.keyframe(k).frame_index);
    }
    for (size_t k = 0; k < loaded_covisibility_.size(); ++k)
      for (int c : loaded_covisibility_[k]) snapshot->covisibility.emplace_back(static_cast<int>(k), c);
    for (size_t k = 0; k < stats_->per_keyframe.size(); ++k)
      for (int c : stats_->per_keyframe[k].covisible)
        snapshot->covisibility.emplace_back(loaded_keyframes_ + static_cast<int>(k), c);
    ref->snapshot = std::move(snapshot);
  }
  return ref;
}

}  // namespace dsm
