// SPDX-License-Identifier: MIT
// Relocalisation in the persistent map: a lost frame is aligned with keyframes of the map instead
// of the last reference alone, and accepted only when it passes the same quality test as tracking
// (tracking_quality.h) and lies within reach of the last trusted pose (TrackingQuality::CheckJump).
// Tracking then resumes against that keyframe, in the same map and scale; TrackingSide::Process holds
// the result as tentative until the next frame confirms it.
//
// Candidates: the reference the camera was lost from, then the `candidates` keyframes with the
// most ORB matches (feature_pose.h) among the kPool whose thumbnails are most like the frame's
// (image/signature.h). Guesses of the frame's pose relative to candidate K, from the last trusted
// pose T_lw (last_from_world) and the velocity V over the k frames lost since:
//   the RANSAC PnP pose of the frame's ORB matches to K's,
//   T_lw T_wK,  V^((k+1)/2) T_lw T_wK,  V^(k+1) T_lw T_wK,  each also turned by +-0.05 rad about
//   the camera's x and y axes,
// and for K other than the reference K's own pose; after lost frames that were sighted (aligned,
// but not yet trusted: MovesAsOneCamera), the newest sighting and it moved on by the step between
// the last two. The coarse energy ranks them; the best two and the sightings' are aligned coarse
// to fine over the whole pyramid (the frame may be far from every keyframe), and the passing
// result with the smallest median residual wins. The features (each keyframe's
// computed once, kept in keyframe_features_), their matches (made once: those that rank a keyframe
// also give its PnP pose) and the candidates' alignments run in parallel on both cores: the mapping
// side waits while the camera is lost.
// Each accepted pose leaves its evidence (TrackingStats::Relocalisation, stats.json `relocalised`):
// the alignment's inlier share beside tracking's, its residual beside the level, whether the
// prediction or three sightings accepted it, and its margin over the best alignment that passed
// at another place.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include <tbb/parallel_for.h>

#include "dsm/image/signature.h"
#include "dsm/system/system_internal.h"
#include "dsm/system/tracking_side.h"
#include "dsm/tracking/feature_pose.h"

namespace dsm {

void TrackingSide::AdoptReference(std::shared_ptr<const TrackingReference> ref, IdleMap& map) {
  map.Republish(ref);
  reference_ = std::move(ref);
  tracker_->SetReference(reference_->pyramid.get(), camera_, reference_->points);
  track_.first_rmse_after_keyframe = 0.0;
}

bool TrackingSide::MovesAsOneCamera(const Sighting& now, double mean_idepth) const {
  // Lost frames a, b and now, relocalised each on its own: a wrong pose (a place that looks alike,
  // a wrong minimum) is found by one frame, not by three that move on smoothly. The step a -> b
  // within the reach of the speed before the loss, the step b -> now within that of the constant
  // velocity a -> b (frames may be missing between them: dropped, or without texture enough).
  // In a loaded map not yet tracked in this run the gap may be longer: the first search computes
  // the features of the keyframes it ranks, and a live camera drops the frames meanwhile.
  const int max_gap = HasTrustedFrame() ? 3 : 10;
  if (sightings_.size() < 2) return false;
  const Sighting& a = sightings_[0];
  const Sighting& b = sightings_[1];
  const int n1 = b.index - a.index, n2 = now.index - b.index;
  if (n1 < 1 || n2 < 1 || n1 > max_gap || n2 > max_gap) return false;
  const SE3d b_from_a = b.cam_from_world * a.cam_from_world.Inverse();
  const SE3d now_from_b = now.cam_from_world * b.cam_from_world.Inverse();
  // A loaded map not yet tracked in this run has no speed before: the map's own (RestoreMap).
  const double speed = HasTrustedFrame() ? track_.velocity.Translation().norm() : loaded_speed_;
  if (!track_.quality.CheckSpeed(b_from_a, n1, speed, mean_idepth).empty()) return false;
  return track_.quality.CheckJump(now_from_b, n2, internal::Scale(b_from_a, 1.0 / n1), mean_idepth).empty();
}

std::vector<int> TrackingSide::RelocalisationCandidates(IdleMap& idle, const ImagePyramid& pyramid,
                                                       const FrameSignature& signature, int ref,
                                                       OrbFeatures* frame_features,
                                                       std::map<int, std::vector<cv::DMatch>>* matches) {
  const Map& map = idle.map();
  std::map<int, OrbFeatures>& keyframe_features = idle.keyframe_features();
  // The reference, then the keyframes with the most feature matches among the kPool most alike by
  // thumbnail (a thumbnail alone ranks poorly after a large change of view). The keyframes'
  // features are computed on first use, in parallel with the frame's.
  constexpr int kPool = 12;
  std::vector<std::pair<double, int>> similar;
  for (int k = 0; k < map.NumKeyframes(); ++k)
    if (k != ref && !map.keyframe(k).retired)
      similar.emplace_back(-Similarity(signature, map.keyframe(k).signature), k);
  const int pool = std::min<int>(kPool, static_cast<int>(similar.size()));
  std::partial_sort(similar.begin(), similar.begin() + pool, similar.end());
  std::vector<int> unknown;  // Keyframes of the pool and the reference without features yet.
  for (int i = 0; i <= pool; ++i) {
    const int k = i < pool ? similar[i].second : ref;
    if (!keyframe_features.count(k)) unknown.push_back(k);
  }
  std::vector<OrbFeatures> detected(unknown.size());
  tbb::parallel_for(size_t{0}, unknown.size() + 1, [&](size_t i) {
    if (i == unknown.size())
      *frame_features = DetectOrbFeatures(pyramid, {});
    else
      detected[i] = DetectOrbFeatures(map.keyframe(unknown[i]).Level0(), {});
  });
  for (size_t i = 0; i < unknown.size(); ++i) keyframe_features.emplace(unknown[i], std::move(detected[i]));
  std::vector<std::vector<cv::DMatch>> pool_matches(pool);
  std::vector<std::tuple<int, int, int>> matched(pool);  // (-matches, keyframe, pool index)
  tbb::parallel_for(0, pool, [&](int i) {
    const int k = similar[i].second;
    pool_matches[i] = MatchFeatures(*frame_features, keyframe_features.at(k), {});
    matched[i] = {-static_cast<int>(pool_matches[i].size()), k, i};
  });
  const int n = std::min<int>(options_.relocalisation.candidates, static_cast<int>(matched.size()));
  std::partial_sort(matched.begin(), matched.begin() + n, matched.end());
  std::vector<int> candidates = {ref};
  for (int i = 0; i < n; ++i) {
    const auto [count, k, in_pool] = matched[i];
    candidates.push_back(k);
    (*matches)[k] = std::move(pool_matches[in_pool]);
  }
  return candidates;
}

std::vector<SE3d> TrackingSide::RelocalisationGuesses(const Map& map, int index, int k, const SE3d& still,
                                                      const std::array<SE3d, 2>& motions,
                                                      const FeaturePose& feature_pose, size_t* first_sighted) const {
  const Keyframe& kf = map.keyframe(k);
  std::vector<SE3d> guesses;
  if (feature_pose.ok) guesses.push_back(feature_pose.frame_from_keyframe);
  for (const SE3d& base : {still, motions[0] * still, motions[1] * still}) {
    guesses.push_back(base);
    for (double angle : {0.05, -0.05})
      for (int axis = 0; axis < 2; ++axis) guesses.push_back(internal::RotationAbout(axis, angle) * base);
  }
  if (k != reference_->keyframe) guesses.push_back(SE3d());
  // The lost frames sighted before this one (MovesAsOneCamera): the camera moves little from
  // frame to frame, so the newest sighting, and it moved on by the step between the last two,
  // are guesses far nearer than anything predicted from before the loss.
  *first_sighted = guesses.size();
  if (!sightings_.empty()) {
    const Sighting& last = sightings_.back();
    guesses.push_back(last.cam_from_world * kf.cam_from_world.Inverse());
    if (sightings_.size() == 2) {
      const Sighting& before = sightings_.front();
      const SE3d step = internal::ScaleSteps(last.cam_from_world * before.cam_from_world.Inverse(),
                                             static_cast<double>(index - last.index) / (last.index - before.index));
      guesses.push_back(step * last.cam_from_world * kf.cam_from_world.Inverse());
    }
  }
  return guesses;
}

TrackingSide::Aligned TrackingSide::AlignWithKeyframe(const SearchFrame& f, IdleMap& idle, int k,
                                                      const OrbFeatures& frame_features,
                                                      const std::vector<cv::DMatch>* matches) const {
  // The two guesses of lowest coarse energy, refined, and the sightings' whatever their coarse energy.
  const Map& map = idle.map();
  const Keyframe& kf = map.keyframe(k);
  Aligned out;
  out.points = idle.PointsSeenIn(k);
  if (out.points.empty()) return out;
  out.pyramid = kf.PyramidOrRebuilt();
  out.tracker = std::make_unique<FrameTracker>(f.tracker);
  FrameTracker& tracker = *out.tracker;
  tracker.SetReference(out.pyramid.get(), camera_, out.points);
  out.mean_idepth = tracker.MeanIdepth();
  const OrbFeatures& features = idle.keyframe_features().at(k);
  const FeaturePose feature_pose = matches != nullptr
                                       ? EstimateFeaturePose(frame_features, features, *matches, out.points, camera_, {})
                                       : EstimateFeaturePose(frame_features, features, out.points, camera_, {});
  size_t first_sighted = 0;
  const std::vector<SE3d> guesses = RelocalisationGuesses(
      map, f.index, k, f.last_from_world * kf.cam_from_world.Inverse(), f.motions, feature_pose, &first_sighted);
  // Brightness: the last trusted frame's. A suspended map's (TrackingSide::Suspend) is from before
  // the camera left it, and the light may have changed since: the best guess with the images'
  // own statistics (signature.h) is aligned too. Not otherwise: between two views of different
  // content the statistics are off by up to ~1.5x themselves, and the extra alignment can win
  // with a wrong pose.
  double alpha, beta;
  internal::RelativeBrightness(f.last_brightness, f.exposure, kf.affine, kf.exposure, &alpha, &beta);
  std::vector<std::pair<double, int>> ranked;
  for (size_t g = 0; g < guesses.size(); ++g)
    ranked.emplace_back(tracker.CoarseEnergyOverAll(*f.pyramid, guesses[g], alpha, beta), static_cast<int>(g));
  std::stable_sort(ranked.begin(), ranked.end());
  const int attempts = std::min<int>(2, static_cast<int>(ranked.size()));
  for (size_t g = 0; g < ranked.size(); ++g) {
    const SE3d& guess = guesses[ranked[g].second];
    if (static_cast<int>(g) < attempts || static_cast<size_t>(ranked[g].second) >= first_sighted)
      out.results.push_back(tracker.Track(*f.pyramid, guess, alpha, beta, f.since));
    else
      out.rest.push_back(guess);
  }
  out.alpha = alpha, out.beta = beta;
  double image_alpha, image_beta;
  if (suspended_ && ImageBrightness(*f.signature, kf.signature, &image_alpha, &image_beta)) {
    std::pair<double, int> best_guess{INFINITY, 0};
    for (size_t g = 0; g < guesses.size(); ++g)
      best_guess = std::min(best_guess, {tracker.CoarseEnergyOverAll(*f.pyramid, guesses[g], image_alpha, image_beta),
                                         static_cast<int>(g)});
    out.results.push_back(tracker.Track(*f.pyramid, guesses[best_guess.second], image_alpha, image_beta, f.since));
  }
  return out;
}

bool TrackingSide::Relocalise(int index, const ImagePyramid& pyramid, const FrameSignature& signature,
                              double exposure, const std::string& plain, TrackResult* result, SE3d* velocity,
                              std::string* reason, TrackingStats::Relocalisation* evidence) {
  // The map is read below: the mapping side must be idle (nothing is handed to it while lost).
  IdleMap& idle = mapping_->WaitUntilIdle(/*urgent=*/true);
  const Map& map = idle.map();
  UpdateReference(false);
  const int ref = reference_->keyframe;
  // The last trusted frame, in the world and in absolute brightness, as the map has it now.
  const SE3d last_from_world = track_.last_frame_from_reference * map.keyframe(ref).cam_from_world;
  const AffineBrightness last_brightness =
      internal::FrameBrightness(map.keyframe(ref).affine, map.keyframe(ref).exposure, track_.alpha, track_.beta,
                                track_.exposure);
  const int since = FramesSinceTrusted(index);

  OrbFeatures frame_features;
  std::map<int, std::vector<cv::DMatch>> matches;
  const std::vector<int> candidates = RelocalisationCandidates(idle, pyramid, signature, ref, &frame_features, &matches);

  // Each candidate keyframe's alignments, in parallel, each to its own slot; they are weighed in
  // order below, so the outcome is that of a sequential loop.
  const SearchFrame lost{index, &pyramid, &signature, exposure, since, last_from_world, last_brightness,
                       {internal::Scale(track_.velocity, 0.5 * since), internal::Scale(track_.velocity, since)},
                       internal::OverLevels(options_.tracker, options_.pyramid_levels)};
  std::vector<Aligned> aligned(candidates.size());
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t c) {
    const auto m = matches.find(candidates[c]);
    aligned[c] = AlignWithKeyframe(lost, idle, candidates[c], frame_features, m != matches.end() ? &m->second : nullptr);
  });

  struct Found {
    TrackResult result;
    int keyframe = -1;
    Aligned* aligned = nullptr;  // The keyframe's points, pyramid and mean inverse depth.
  };
  // best: passed the quality test and the jump check; sighted: passed the quality test.
  std::optional<Found> best, sighted;
  // Every alignment that passed the quality test: the camera in the world and its median residual.
  std::vector<std::pair<SE3d, double>> passed;
  const auto cam_from_world = [&](const Found& f) {
    return f.result.frame_from_keyframe * map.keyframe(f.keyframe).cam_from_world;
  };
  // A loaded map not yet tracked in this run (RestoreMap) has no trusted frame to predict from or
  // to measure a step against: its frames relocalise by three sightings alone.
  const bool trusted = HasTrustedFrame();
  const bool predicted = trusted && plain.empty() && since <= options_.relocalisation.max_predicted_frames;
  // Why not, as told: the failure of the attempt with the most of its keyframe's points in view,
  // not of the last one tried (often a keyframe that does not see the place at all, whose "too few
  // points in view" would hide why the reference's alignment failed).
  std::string why;
  double why_visibility;
  const auto weigh = [&] {
    best.reset(), sighted.reset(), passed.clear();
    why = "no keyframe to relocalise against", why_visibility = -1.0;
    for (size_t c = 0; c < candidates.size(); ++c) {
      const int k = candidates[c];
      Aligned& a = aligned[c];
      for (const TrackResult& r : a.results) {
        const SE3d step =
            trusted ? r.frame_from_keyframe * map.keyframe(k).cam_from_world * last_from_world.Inverse() : SE3d();
        std::string fail = track_.quality.CheckTracking(r, step, since, a.mean_idepth, k != ref);
        if (fail.empty()) passed.emplace_back(r.frame_from_keyframe * map.keyframe(k).cam_from_world, r.residual_p50);
        if (fail.empty() && (!sighted || r.residual_p50 < sighted->result.residual_p50))
          sighted = Found{r, k, &a};
        if (fail.empty()) {
          fail = predicted       ? track_.quality.CheckJump(step, since, track_.velocity, a.mean_idepth)
                 : !plain.empty() ? plain + ": one frame does not relocalise"
                                  : "lost too long to predict the pose";
        }
        if (!fail.empty()) {
          if (r.visibility > why_visibility) why = fail, why_visibility = r.visibility;
          continue;
        }
        if (!best || r.residual_p50 < best->result.residual_p50) best = Found{r, k, &a};
      }
    }
  };
  weigh();
  // Nothing found: the reference's other guesses are refined too, and all weighed again. The
  // coarse energy ranks poorly between views that overlap the keyframe's by different shares, so
  // the right pose may come from a guess ranked low. Only then: a frame that relocalises from the
  // two best of each keyframe is found as before, and the cost (all the guesses refined, not two)
  // is paid by frames that would fail.
  const bool found = best || (sighted && MovesAsOneCamera({index, cam_from_world(*sighted)},
                                                          sighted->aligned->mean_idepth));
  if (!found && !aligned.empty() && !aligned[0].rest.empty()) {
    Aligned& a = aligned[0];  // The reference's.
    std::vector<TrackResult> more(a.rest.size());
    tbb::parallel_for(size_t{0}, a.rest.size(),
                      [&](size_t g) { more[g] = a.tracker->Track(pyramid, a.rest[g], a.alpha, a.beta, since); });
    a.results.insert(a.results.end(), more.begin(), more.end());
    weigh();
  }
  // The camera's motion per frame through the loss: from the last trusted frame (a pose within
  // reach of the prediction), or from the sighting before (three sightings that move as one
  // camera). The next frame is tracked from there: a frame after a few dropped or lost ones is
  // no longer where the relocalised one was, and from that guess the alignment can end in a
  // wrong minimum (a near occluder's parallax) that the residual level just restarted lets pass.
  if (best) *velocity = internal::ScaleSteps(cam_from_world(*best) * last_from_world.Inverse(), 1.0 / since);
  const bool by_prediction = best.has_value();
  if (!best && sighted) {
    const Sighting now{index, cam_from_world(*sighted)};
    if (MovesAsOneCamera(now, sighted->aligned->mean_idepth)) {
      const Sighting& before = sightings_.back();
      *velocity = internal::ScaleSteps(now.cam_from_world * before.cam_from_world.Inverse(), 1.0 / (index - before.index));
      best = std::move(sighted);
    } else {
      sightings_.push_back(now);
      if (sightings_.size() > 2) sightings_.pop_front();
    }
  } else if (!best) {
    sightings_.clear();
  }
  if (!best) {
    *reason = "relocalisation failed: " + why;
    return false;
  }
  sightings_.clear();
  const SE3d winner = cam_from_world(*best);
  *evidence = {index, best->keyframe, since, by_prediction, best->result.inlier_ratio,
               track_.quality.InlierLevel(), best->result.residual_p50 / std::max(track_.quality.ResidualLevel(), 1e-9),
               0.0};
  for (const auto& [pose, p50] : passed)
    if (internal::OtherPlace(pose, winner, best->aligned->mean_idepth) &&
        (evidence->margin == 0.0 || p50 / best->result.residual_p50 < evidence->margin))
      evidence->margin = p50 / best->result.residual_p50;
  // The keyframe becomes the reference of both sides: the mapping side is idle, and the next
  // keyframe it maps is made relative to it.
  if (best->keyframe != ref)
    AdoptReference(idle.MakeReference(best->keyframe, std::move(best->aligned->points), best->aligned->pyramid), idle);
  *result = best->result;
  return true;
}

}  // namespace dsm
