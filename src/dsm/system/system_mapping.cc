// SPDX-License-Identifier: MIT
// Keyframe mapping: observations, window, activation, bundle adjustment, culling, candidates.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "dsm/mapping/activation.h"
#include "dsm/mapping/candidate_selector.h"
#include "dsm/mapping/window.h"
#include "dsm/optimization/pba.h"
#include "dsm/system/system.h"
#include "dsm/tracking/frame_tracker.h"

namespace dsm {

namespace {

// Projection of point p into keyframe `target`: pixel and inverse depth; false if behind or outside.
bool ProjectPoint(const Map& map, const PinholeCamera& camera, const Point& p, int target, float border,
                  Eigen::Vector2f* pixel, float* idepth) {
  const Keyframe& host = map.keyframe(p.host);
  const Keyframe& kf = map.keyframe(target);
  const Eigen::Vector3d p_host = camera.Unproject(p.pixel.x(), p.pixel.y()) / p.idepth;
  const Eigen::Vector3d p_target = kf.cam_from_world * (host.cam_from_world.Inverse() * p_host);
  if (p_target.z() <= 1e-6) return false;
  const Eigen::Vector2d u = camera.Project(p_target);
  if (u.x() < border || u.y() < border || u.x() > camera.width - 1 - border || u.y() > camera.height - 1 - border)
    return false;
  *pixel = u.cast<float>();
  *idepth = static_cast<float>(1.0 / p_target.z());
  return true;
}

}  // namespace

void System::CreateKeyframe(int index, int64_t t_ns, std::unique_ptr<ImagePyramid> pyramid, double exposure,
                            const SE3d& cam_from_world, const AffineBrightness& affine) {
  auto kf = std::make_unique<Keyframe>();
  kf->frame_index = index;
  kf->t_ns = t_ns;
  kf->cam_from_world = cam_from_world;
  kf->affine = affine;
  kf->exposure = exposure;
  kf->pyramid = std::move(*pyramid);
  kf->error_model = DefaultErrorModel(options_.pba.robust);
  map_.AddKeyframe(std::move(kf));
  ++stats_.keyframes;
}

std::vector<int> System::ActivePointIds() const {
  std::vector<int> ids;
  for (int kf : window_)
    for (int pid : map_.keyframe(kf).points)
      if (!map_.point(pid).removed) ids.push_back(pid);
  return ids;
}

void System::MapNewKeyframe(int kf) {
  // Observations of the window's points in the new keyframe (the PBA verifies them).
  for (int pid : ActivePointIds()) {
    Point& p = map_.point(pid);
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map_, camera_, p, kf, 4.f, &px, &rho)) p.observations.push_back({kf, false});
  }
  window_.push_back(kf);
  const int drop = SelectKeyframeToDrop(map_, window_, options_.window);
  if (drop >= 0) {
    window_.erase(std::find(window_.begin(), window_.end(), drop));
    candidates_.erase(drop);
  }
  ActivateCandidates(kf);
  const PbaSummary pba = RunPba(&map_, camera_, window_, options_.pba);
  stats_.pba_ms.push_back(pba.time_ms);
  CullPoints();
  SelectCandidates(kf);
  SetTrackingReference();
}

void System::ActivateCandidates(int newest) {
  const std::vector<int> active = ActivePointIds();
  DistanceMap distance(camera_.width, camera_.height);
  for (int pid : active) {
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map_, camera_, map_.point(pid), newest, 0.f, &px, &rho)) distance.Add(px);
  }
  // Keep the window near its target number of points by adapting the spacing.
  const int target = options_.activation.target_points;
  if (static_cast<int>(active.size()) < 0.8 * target) min_activation_distance_px_ = std::max(2.f, min_activation_distance_px_ - 1.f);
  if (static_cast<int>(active.size()) > 1.2 * target) min_activation_distance_px_ += 1.f;

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
      if (ProjectPoint(map_, camera_, probe, newest, 0.f, &px, &rho)) distance.Add(px);
    }
  }
}

void System::CullPoints() {
  const int num_keyframes = map_.NumKeyframes();
  for (int pid : ActivePointIds()) {
    Point& p = map_.point(pid);
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
  }
}

void System::SelectCandidates(int kf) {
  std::vector<Candidate>& list = candidates_[kf];
  list.clear();
  const Keyframe& keyframe = map_.keyframe(kf);
  for (const SelectedPixel& s : dsm::SelectCandidates(keyframe.pyramid, options_.candidates)) {
    Candidate c;
    if (MakeCandidate(keyframe.pyramid, s.pixel, &c)) list.push_back(c);
  }
}

void System::SetTrackingReference() {
  const int newest = window_.back();
  std::vector<ReferencePoint> points;
  for (int pid : ActivePointIds()) {
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map_, camera_, map_.point(pid), newest, 2.f, &px, &rho)) points.push_back({px, rho});
  }
  if (newest != reference_) {
    // The new reference is the keyframe made from the last tracked frame.
    last_frame_from_reference_ = SE3d();
    last_alpha_ = 0.0;
    last_beta_ = 0.0;
  }
  reference_ = newest;
  tracker_->SetReference(&map_.keyframe(newest).pyramid, camera_, points);
  first_rmse_after_keyframe_ = 0.0;
}

}  // namespace dsm
