// SPDX-License-Identifier: MIT
// Loop closure (LoopClosureOptions, --mode dsm): a camera that comes back after a long path has
// drifted beyond the reach of re-observation (the photometric alignment converges from a pixel or
// two away), so the window sees the old place but maps it anew. Appearance finds it, geometry
// corrects the map, and the persistent map's own mechanism joins the two passes:
//
// 1. Detection. Each new keyframe's bag of words (place/vocabulary.h, its ORB features) is scored
//    against the map's keyframes that the window has not already joined: not in the window, and
//    none of whose points the window observes. The floor is 0.8 of the score against the keyframe
//    before (the same place, a step apart). Candidates are grouped with their neighbours in time,
//    and a group found again by consistent_keyframes keyframes in a row is a detection
//    (place/place_groups.h).
// 2. Verification. ORB matches between the keyframe and the group's best candidate take inverse
//    depths from the map points near each keypoint in both views; RANSAC on a Sim(3) between the
//    two cameras (geometry/sim3_ransac.h) needs min_inliers, then the keyframe's image is aligned
//    directly against the candidate's points from that pose (the frame tracker, over the whole
//    pyramid) and must pass the quality test's inlier share, fit the candidate's points with a
//    median residual within kMaxResidualToScale of the keyframe's own error scale, and stay near
//    the feature pose. The map as it is is the other hypothesis: the keyframe is aligned with the
//    candidate's points from the pose the map gives them too, and where that lands elsewhere, the
//    loop must fit clearly better (kClearlyBetter). The correction (the keyframe's move plus its
//    turn at the scene's depth) may not exceed a tenth of the path along the map's links since
//    the candidate (LinkedPath: consecutive keyframes, and keyframes that share observations, the
//    newest left out): drift is a few percent of the path it grew along, and a camera that came
//    back to a place and re-observed it drifted only along that short way; a larger jump is a
//    place that looks the same (perceptual aliasing). Nor is a loop closed whose correction moves
//    the candidate's points in the keyframe by less than kReobservePx: re-observation joins the
//    two passes from there by itself.
// 3. Correction. A Sim(3) pose graph (optimization/pose_graph.h) over every keyframe: edges
//    between consecutive keyframes and between keyframes that share at least kMinSharedPoints
//    observations, measured at the poses before, and the loop edge k_from_c; the first keyframe
//    (and a loaded map's) held. Each keyframe takes its new pose, its points their host's scale
//    (inverse depth times s: points are stored relative to their host). The next keyframes select
//    the old keyframes as covisible and re-observe their points, and the loop bundle adjustment
//    (MappingSide::AdjustLoop) refines the loop region once they reach back far enough.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "dsm/geometry/sim3_ransac.h"
#include "dsm/optimization/pose_graph.h"
#include "dsm/place/place_groups.h"
#include "dsm/system/mapping_side.h"
#include "dsm/system/system_internal.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/tracking/frame_tracker.h"
#include "dsm/util/median.h"

namespace dsm {

namespace {

constexpr double kFloorShare = 0.8;      // Of the score against the keyframe before.
constexpr double kMaxCorrectionShare = 0.1;  // Of the path since the candidate.
constexpr double kReobservePx = 4.0;     // A loop this near is left to re-observation.
constexpr int kLoopGap = 10;            // Keyframes after a closure before the next one.
constexpr double kLoopWeight = 10.0;     // Of the loop's pose-graph edges against the map's.
constexpr int kMinSharedPoints = 50;     // Observations that make a pose-graph edge between two keyframes.
constexpr int kLinkWindows = 8;          // Windows of the newest keyframes whose links bound no loop.
constexpr double kMaxRefineDeg = 5.0;    // The direct alignment stays this near the feature pose ...
constexpr double kMaxRefineStep = 0.2;   // ... and this near over the candidate's mean depth.
constexpr double kMaxResidualToScale = 2.0;  // The alignment's median residual, of kf's error scale.
constexpr double kClearlyBetter = 1.25;  // A loop's median residual below the map's own by this factor.

// The distance the centres of keyframes `from` .. `to` travel, the retired ones left out.
double PathBetween(const Map& map, int from, int to) {
  double path = 0.0;
  for (int k = from + 1, prev = from; k <= to; ++k) {
    if (map.keyframe(k).retired) continue;
    path += (map.keyframe(k).Centre() - map.keyframe(prev).Centre()).norm();
    prev = k;
  }
  return path;
}

// Observations shared by each pair of live keyframes (i < j): points hosted by one with an inlier
// observation in the other.
std::map<std::pair<int, int>, int> SharedObservations(const Map& map) {
  std::map<std::pair<int, int>, int> shared;
  for (int pid = 0; pid < map.NumPoints(); ++pid) {
    const Point& p = map.point(pid);
    if (p.removed) continue;
    for (const Observation& o : p.observations)
      if (!o.outlier && !map.keyframe(o.target).retired) ++shared[{std::min(p.host, o.target), std::max(p.host, o.target)}];
  }
  return shared;
}

// The shortest path between keyframes `from` and `to` along the links that placed them: consecutive
// live keyframes, and pairs older than `settled` sharing at least kMinSharedPoints observations,
// each link as long as the distance between the two centres (Dijkstra). Drift grows along these
// links, so a camera that came back to a place and re-observed it has a short path to it however
// long it walked since. The links of the keyframes mapped since the camera may have come back are
// left out (a place is recognised up to several windows after the return): re-observation may
// have joined them to the place being judged where the drift had them.
double LinkedPath(const Map& map, const std::map<std::pair<int, int>, int>& shared, int from, int to, int settled) {
  std::map<int, std::vector<int>> links;
  int prev = -1;
  for (int k = 0; k < map.NumKeyframes(); ++k) {
    if (map.keyframe(k).retired) continue;
    if (prev >= 0) links[prev].push_back(k), links[k].push_back(prev);
    prev = k;
  }
  for (const auto& [pair, count] : shared)
    if (count >= kMinSharedPoints && pair.second < settled) links[pair.first].push_back(pair.second), links[pair.second].push_back(pair.first);
  std::map<int, double> dist{{from, 0.0}};
  std::set<std::pair<double, int>> open{{0.0, from}};
  while (!open.empty()) {
    const auto [d, k] = *open.begin();
    open.erase(open.begin());
    if (k == to) return d;
    for (int n : links[k]) {
      const double nd = d + (map.keyframe(n).Centre() - map.keyframe(k).Centre()).norm();
      const auto it = dist.find(n);
      if (it != dist.end() && it->second <= nd) continue;
      if (it != dist.end()) open.erase({it->second, n});
      dist[n] = nd;
      open.insert({nd, n});
    }
  }
  return PathBetween(map, from, to);
}

}  // namespace

const OrbFeatures& MappingSide::KeyframeFeatures(int k) {
  auto it = keyframe_features_.find(k);
  if (it == keyframe_features_.end())
    it = keyframe_features_.emplace(k, DetectOrbFeatures(map_.keyframe(k).Level0(), {})).first;
  return it->second;
}

bool MappingSide::LoopClosureActive() const {
  return options_.loop_closure.enabled && options_.mode == MapMode::kFull && !localizing_ && loop_.vocabulary != nullptr;
}

void MappingSide::AddToPlaceIndex(int k) {
  places_->Add(this, k, loop_.vocabulary->Transform(KeyframeFeatures(k).descriptors));
}

bool MappingSide::DetectAndCloseLoop(int kf) {
  if (!LoopClosureActive()) return false;
  const auto start = std::chrono::steady_clock::now();
  AddToPlaceIndex(kf);
  const BowVector& bow = *places_->Bow(this, kf);
  // The floor: a share of the score against the keyframe before (the same place, a step apart).
  const int before = window_.size() >= 2 ? window_[window_.size() - 2] : -1;
  if (before < 0 || places_->Bow(this, before) == nullptr) return false;
  const double floor = kFloorShare * Vocabulary::Score(bow, *places_->Bow(this, before));
  const int recent = kf - 2 * (options_.window.temporal_keyframes + options_.window.covisible_keyframes);
  std::vector<std::pair<double, int>> scored = places_->Query(
      this, bow, floor, [&](int k) { return k >= recent || map_.keyframe(k).retired; });
  if (!scored.empty()) {
    // Keyframes the window has joined already: its own, and the hosts of the points it observes
    // (a scan of the map, made only when there are candidates to judge). A candidate near one of
    // them (in its group) shows a place the map has joined already.
    std::set<int> joined(window_.begin(), window_.end());
    joined.insert(covisible_.begin(), covisible_.end());
    for (int pid = 0; pid < map_.NumPoints(); ++pid) {
      const Point& p = map_.point(pid);
      if (p.removed || joined.count(p.host)) continue;
      for (const Observation& o : p.observations)
        if (!o.outlier && std::find(window_.begin(), window_.end(), o.target) != window_.end()) {
          joined.insert(p.host);
          break;
        }
    }
    std::erase_if(scored, [&](const std::pair<double, int>& candidate) {
      const auto near = joined.lower_bound(candidate.second - PlaceGroups::kReach);
      return near != joined.end() && InSamePlace(*near, candidate.second);
    });
  }
  std::vector<int> to_verify = ConsistentGroups(scored, options_.loop_closure.consistent_keyframes, &loop_.groups,
                                                     &stats_->loops_detected);
  // One loop is closed at a time: the keyframes after a closure re-observe the old place, and the
  // loop adjustment follows.
  if (loop_.last_loop_keyframe >= 0 && kf - loop_.last_loop_keyframe < kLoopGap) to_verify.clear();
  // A place is closed once: the keyframes after a closure join it by re-observation, and a second
  // verification against its neighbours (a few matches at the closure's edge) can only disturb it.
  std::erase_if(to_verify, [&](int c) {
    return std::any_of(stats_->loops_closed.begin(), stats_->loops_closed.end(),
                       [&](const MappingStats::LoopClosure& l) { return InSamePlace(c, l.candidate); });
  });
  // The observations each pair of keyframes shares: for the drift bound and the pose graph, counted
  // once the first candidate is verified (the map does not change until the loop is corrected).
  std::optional<std::map<std::pair<int, int>, int>> shared;
  for (int c : to_verify) {
    LoopMatch match;
    if (!VerifyLoop(kf, *this, c, &match)) continue;
    if (!shared) shared = SharedObservations(map_);
    // How far the loop would move the keyframe, as a share of the path since the candidate: drift
    // of a few percent is closed; a place tens of percent of the path away is another place that
    // looks the same (a twin room, the next floor of a building), whatever the views say.
    // The path is the one the map's links give (LinkedPath): a place re-observed since has drifted
    // only along the links that joined it. The move counts the turn too, as the distance it moves
    // the scene at its depth.
    const Sim3d moved = match.k_from_c * Sim3d(map_.keyframe(c).cam_from_world);
    const SE3d& now = map_.keyframe(kf).cam_from_world;
    const double move = (moved.Inverse().Translation() - map_.keyframe(kf).Centre()).norm() +
                        (moved.So3() * now.So3().Inverse()).Log().norm() * match.depth;
    const int settled = kf - kLinkWindows * (options_.window.temporal_keyframes + options_.window.covisible_keyframes);
    const double path = LinkedPath(map_, *shared, c, kf, settled);
    if (move > kMaxCorrectionShare * path) continue;
    if (match.shift_px < kReobservePx) continue;
    CorrectLoop(kf, match, *shared);
    MappingStats::LoopClosure& closed = stats_->loops_closed.back();
    closed.inliers = match.inliers;
    closed.residual_ratio = match.residual_ratio;
    closed.shift_px = match.shift_px;
    closed.correction_share = move / path;
    closed.margin = match.margin;
    closed.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    loop_.groups.clear();
    loop_.last_loop_keyframe = kf;
    return true;
  }
  DetectMerge(kf, bow, floor);
  return false;
}

void MappingSide::DetectMerge(int kf, const BowVector& bow, double floor) {
  if (loop_.merge_ready.load() >= 0) return;  // One merge at a time.
  const std::vector<AtlasPlaces::Candidate>& candidates = places_->merge_candidates();
  // A map's groups last while it stays a candidate.
  std::erase_if(loop_.merge_groups, [&](const auto& groups) {
    return std::none_of(candidates.begin(), candidates.end(),
                        [&](const AtlasPlaces::Candidate& c) { return c.serial == groups.first; });
  });
  for (const AtlasPlaces::Candidate& source : candidates) {
    const Map& other = source.map->map();
    // Residuals of one map sample all its images alike (Map::interpolation).
    if (other.interpolation() != map_.interpolation()) continue;
    const std::vector<std::pair<double, int>> scored =
        places_->Query(source.map, bow, floor, [&](int k) { return other.keyframe(k).retired; });
    int found = 0;
    for (int c : ConsistentGroups(scored, options_.loop_closure.consistent_keyframes,
                                  &loop_.merge_groups[source.serial], &found)) {
      LoopMatch match;
      if (!VerifyLoop(kf, *source.map, c, &match)) continue;
      // Two maps share no path, so no share of it bounds the correction: the verification alone
      // decides (perceptual aliasing between maps is not caught).
      loop_.pending_merge = LoopState::PendingMerge{source.map, kf, match};
      loop_.merge_ready.store(source.id);
      return;
    }
  }
}

bool MappingSide::VerifyLoop(int kf, PlaceMap& owner, int c, LoopMatch* match) {
  const OrbFeatures& fk = KeyframeFeatures(kf);
  const OrbFeatures& fc = owner.KeyframeFeatures(c);
  const std::vector<cv::DMatch> matches = MatchFeatures(fk, fc, {});
  const std::vector<ReferencePoint> points_c = owner.PointsSeenIn(c);
  const std::vector<float> rho_k = KeypointInverseDepths(fk, PointsSeenIn(kf), {});
  const std::vector<float> rho_c = KeypointInverseDepths(fc, points_c, {});
  std::vector<Eigen::Vector3d> in_k, in_c;
  for (const cv::DMatch& m : matches) {
    const float a = rho_k[m.queryIdx], b = rho_c[m.trainIdx];
    if (a <= 0.f || b <= 0.f) continue;
    const cv::Point2f& u = fk.keypoints[m.queryIdx].pt;
    const cv::Point2f& v = fc.keypoints[m.trainIdx].pt;
    in_k.push_back(camera_.Unproject(u.x, u.y) / a);
    in_c.push_back(camera_.Unproject(v.x, v.y) / b);
  }
  Sim3RansacOptions ransac;
  ransac.min_inliers = options_.loop_closure.min_inliers;
  const Sim3RansacResult r = EstimateSim3Ransac(in_k, in_c, camera_, ransac);  // c_from_k
  if (!r.ok) return false;
  // Direct alignment of the keyframe against the candidate's points, at the candidate's scale.
  const Keyframe& k = map_.keyframe(kf);
  const Keyframe& old = owner.map().keyframe(c);
  const TrackerOptions tracker_options = internal::OverLevels(options_.tracker, options_.pyramid_levels);
  const std::shared_ptr<const ImagePyramid> pyramid = old.PyramidOrRebuilt();
  FrameTracker tracker(tracker_options);
  tracker.SetReference(pyramid.get(), camera_, points_c);
  const SO3d r_kc = r.b_from_a.So3().Inverse();
  const SE3d guess(r_kc, -(r_kc * r.b_from_a.Translation()));
  // The brightness change between the two views from their images' statistics: the keyframes'
  // affine brightness has drifted along the loop as their poses have.
  double alpha = 0.0, beta = 0.0;
  ImageBrightness(k.signature, old.signature, &alpha, &beta);
  const TrackResult t = tracker.Track(k.Pyramid(), guess, alpha, beta);
  const SE3d change = t.frame_from_keyframe * guess.Inverse();
  if (!t.ok || t.inlier_ratio < options_.quality.min_inlier_ratio) return false;
  // The candidate's points must fit the keyframe as well as the map's own observations in it do:
  // an alignment that its fitted model calls all inliers at several times the keyframe's error
  // scale is a view the candidate only resembles.
  if (t.residual_p50 > kMaxResidualToScale * k.error_model.sigma) return false;
  if (change.So3().Log().norm() * 180.0 / M_PI > kMaxRefineDeg ||
      change.Translation().norm() * tracker.MeanIdepth() > kMaxRefineStep)
    return false;
  // Where the candidate's points land in kf with the pose it has and with the loop's: when they
  // land within reach of the photometric alignment, re-observation joins the two passes by
  // itself, with the bundle adjustment's accuracy, and the loop is left to it.
  const SE3d k_from_c_now = k.cam_from_world * old.cam_from_world.Inverse();
  // The median distance (px) between where the candidate's points land in kf from poses a and b.
  const auto median_shift = [&](const SE3d& a, const SE3d& b) {
    std::vector<float> shifts;
    for (const ReferencePoint& p : points_c) {
      const Eigen::Vector3d x = camera_.Unproject(p.pixel.x(), p.pixel.y()) / p.idepth;
      const Eigen::Vector3d in_a = a * x, in_b = b * x;
      if (in_a.z() > 0.0 && in_b.z() > 0.0)
        shifts.push_back(static_cast<float>((camera_.Project(in_a) - camera_.Project(in_b)).norm()));
    }
    return shifts.empty() ? 0.0 : static_cast<double>(Median(shifts));
  };
  match->shift_px = median_shift(k_from_c_now, t.frame_from_keyframe);
  // The map as it is is the other hypothesis: the keyframe aligned with the candidate's points from
  // the pose the map gives them. Where that lands elsewhere than the loop and fits at least nearly
  // as well, the view does not tell the two apart (a place that repeats, a wrong RANSAC pose
  // polished by the alignment) and the map is left as it is.
  // (Another map's poses are in another frame: there the map offers no such hypothesis.)
  const TrackResult as_is = &owner == static_cast<PlaceMap*>(this) ? tracker.Track(k.Pyramid(), k_from_c_now, alpha, beta) : TrackResult{};
  if (as_is.ok && as_is.inlier_ratio >= options_.quality.min_inlier_ratio) {
    if (median_shift(as_is.frame_from_keyframe, t.frame_from_keyframe) >= kReobservePx) {
      if (t.residual_p50 * kClearlyBetter > as_is.residual_p50) return false;
      match->margin = as_is.residual_p50 / t.residual_p50;
    }
  }
  // The scale between the two: the median ratio of each inlier's depth in kf as the candidate's
  // map has it (through the aligned pose) to its depth in kf's own map. Umeyama's least squares
  // over the 3D points weighs the far ones, whose depths are the least certain, the most.
  std::vector<double> ratios;
  for (int i : r.inliers) {
    const double z = (t.frame_from_keyframe * in_c[i]).z();
    if (z > 0.0) ratios.push_back(z / in_k[i].z());
  }
  if (ratios.size() < static_cast<size_t>(options_.loop_closure.min_inliers)) return false;
  const double s = Median(ratios);
  match->candidate = c;
  match->depth = 1.0 / tracker.MeanIdepth();
  match->residual_ratio = t.residual_p50 / k.error_model.sigma;
  match->k_from_c = Sim3d(1.0 / s, t.frame_from_keyframe.So3(), t.frame_from_keyframe.Translation() / s);
  match->alpha = t.alpha - std::log(k.exposure / old.exposure);
  match->beta = t.beta;
  match->inliers = static_cast<int>(r.inliers.size());
  return true;
}

void MappingSide::CorrectLoop(int kf, const LoopMatch& match, const std::map<std::pair<int, int>, int>& shared) {
  const int c = match.candidate;
  const std::vector<int> ids = AllKeyframes();
  std::map<int, int> node;
  std::vector<Sim3d> start;
  for (int k : ids) node[k] = static_cast<int>(start.size()), start.emplace_back(map_.keyframe(k).cam_from_world);
  // Edges: consecutive keyframes, and keyframes that share observations, as the map has them.
  const int span = 2 * (options_.window.temporal_keyframes + options_.window.covisible_keyframes);
  std::vector<PoseGraphEdge> edges;
  const auto measured = [&](int i, int j) { return start[node[i]] * start[node[j]].Inverse(); };
  // A block merged from another map (MergeVerified) is joined to the rest by its merge, not by
  // the ids next to it.
  const auto block = [&](int k) {
    for (size_t b = 0; b < loop_.merged_blocks.size(); ++b)
      if (loop_.merged_blocks[b].Contains(k)) return static_cast<int>(b);
    return -1;
  };
  for (size_t n = 1; n < ids.size(); ++n)
    if (block(ids[n]) == block(ids[n - 1]))
      edges.push_back({node[ids[n]], node[ids[n - 1]], measured(ids[n], ids[n - 1]), 1.0});
  for (const MergedBlock& b : loop_.merged_blocks)
    if (node.count(b.keyframe) && node.count(b.candidate))
      edges.push_back({node[b.keyframe], node[b.candidate], measured(b.keyframe, b.candidate), 1.0});
  for (const auto& [pair, count] : shared) {
    const auto [i, j] = pair;
    // Keyframes far apart in time that share points were joined by re-observation, which may
    // have held them where the drift had them when they met: the loop edge is the judge there.
    if (count < kMinSharedPoints || !node.count(i) || !node.count(j) || j - i > span) continue;
    const int ni = node[i], nj = node[j];
    if (std::abs(ni - nj) == 1 && block(i) == block(j)) continue;  // Consecutive: there already.
    edges.push_back({nj, ni, measured(j, i), 1.0});
  }
  // The loop: kf to c as verified, and every other keyframe of the temporal window to c through
  // kf (the window's own geometry), weighted so that the window lands where the verification puts
  // it and the loop's error goes to the path between.
  const int first_loop_edge = static_cast<int>(edges.size());
  for (int w : window_) {
    if (!node.count(w)) continue;
    edges.push_back({node[w], node[c], measured(w, kf) * match.k_from_c, kLoopWeight});
  }
  std::vector<int> fixed;
  for (int k : HeldWithLoaded({ids.front()})) fixed.push_back(node[k]);
  // The path up to the keyframe, before the correction (for the correction's share of it).
  const double path = PathBetween(map_, ids.front(), kf);
  const SE3d before = map_.keyframe(kf).cam_from_world;
  const PoseGraphResult graph = OptimizePoseGraph(start, edges, fixed);
  for (int k : ids) {
    const Sim3d& s = graph.cam_from_world[node[k]];
    Keyframe& keyframe = map_.keyframe(k);
    keyframe.cam_from_world = SE3d(s.So3(), s.Translation() / s.Scale());
    for (int pid : keyframe.points) map_.point(pid).idepth *= static_cast<float>(s.Scale());
    if (k >= static_cast<int>(keyframe_scale_.size())) keyframe_scale_.resize(k + 1, 1.0);
    keyframe_scale_[k] *= s.Scale();
  }
  // The brightness along the same edges: the map's relative brightness, and the loop's as the
  // direct alignment found it.
  std::vector<Eigen::Vector2d> ab;
  for (int k : ids) ab.emplace_back(map_.keyframe(k).affine.a, map_.keyframe(k).affine.b);
  std::vector<BrightnessEdge> brightness;
  for (size_t n = 0; n < edges.size(); ++n) {
    const PoseGraphEdge& e = edges[n];
    if (static_cast<int>(n) >= first_loop_edge) {
      if (e.i == node[kf]) brightness.push_back({e.j, e.i, match.alpha, match.beta});
      continue;
    }
    const double alpha = ab[e.i].x() - ab[e.j].x();
    brightness.push_back({e.j, e.i, alpha, ab[e.i].y() - std::exp(alpha) * ab[e.j].y()});
  }
  const std::vector<Eigen::Vector2d> corrected = OptimizeBrightnessGraph(ab, brightness, fixed);
  for (int k : ids) map_.keyframe(k).affine = {corrected[node[k]].x(), corrected[node[k]].y()};
  const SE3d& after = map_.keyframe(kf).cam_from_world;
  MappingStats::LoopClosure closed;
  closed.frame = map_.keyframe(kf).frame_index;
  closed.keyframe = kf;
  closed.candidate = c;
  closed.translation_share = path > 0.0 ? (after.Inverse().Translation() - before.Inverse().Translation()).norm() / path : 0.0;
  closed.rotation_deg = (after.So3() * before.So3().Inverse()).Log().norm() * 180.0 / M_PI;
  closed.scale = graph.cam_from_world[node[kf]].Scale();
  stats_->loops_closed.push_back(closed);
  // The next keyframes re-observe the old points; once their covisible keyframes reach back far
  // enough, the loop is bundle-adjusted (AdjustLoop).
  loop_ba_pending_ = true;
}

}  // namespace dsm
