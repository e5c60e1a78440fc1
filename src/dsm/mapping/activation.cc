// SPDX-License-Identifier: MIT
#include "dsm/mapping/activation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dsm/util/check.h"

namespace dsm {

void ActivationOptions::Validate() const {
  if (target_points < 50) throw InputError("activation.target_points must be at least 50");
}

DistanceMap::DistanceMap(int width, int height)
    : w_(width / 2), h_(height / 2), d_(static_cast<size_t>(w_) * h_, std::numeric_limits<float>::infinity()) {}

void DistanceMap::Add(const Eigen::Vector2f& pixel) {
  // Local update within a radius large enough for any activation threshold in use.
  constexpr int kRadius = 16;  // Half-resolution cells (32 level-0 pixels).
  const float cx = 0.5f * pixel.x(), cy = 0.5f * pixel.y();
  const int x0 = std::max(0, static_cast<int>(cx) - kRadius), x1 = std::min(w_ - 1, static_cast<int>(cx) + kRadius);
  const int y0 = std::max(0, static_cast<int>(cy) - kRadius), y1 = std::min(h_ - 1, static_cast<int>(cy) + kRadius);
  for (int y = y0; y <= y1; ++y) {
    const float dy2 = (y - cy) * (y - cy);
    float* row = d_.data() + static_cast<size_t>(y) * w_;
    for (int x = x0; x <= x1; ++x) row[x] = std::min(row[x], 2.f * std::sqrt((x - cx) * (x - cx) + dy2));
  }
}

float DistanceMap::Distance(const Eigen::Vector2f& pixel) const {
  const int x = std::clamp(static_cast<int>(0.5f * pixel.x()), 0, w_ - 1);
  const int y = std::clamp(static_cast<int>(0.5f * pixel.y()), 0, h_ - 1);
  return d_[static_cast<size_t>(y) * w_ + x];
}

bool RefineCandidate(const Map& map, const PinholeCamera& camera, int host_id, const Candidate& c,
                     const std::vector<int>& targets, const ActivationOptions& options, RefinedPoint* out) {
  const Keyframe& host = map.keyframe(host_id);
  HostPatch patch;
  if (!SampleHostPatch(host.Pyramid(), 0, c.pixel, map.interpolation(), &patch)) return false;
  float rho = c.Idepth();
  if (!(rho > 0.f)) return false;
  struct Target {
    int id;
    Eigen::Matrix3f R;
    Eigen::Vector3f t;
    const Keyframe* kf;
  };
  std::vector<Target> ts;
  for (int id : targets) {
    if (id == host_id) continue;
    const Keyframe& kf = map.keyframe(id);
    const SE3d T = kf.cam_from_world * host.cam_from_world.Inverse();
    ts.push_back({id, T.Rotation().cast<float>(), T.Translation().cast<float>(), &kf});
  }
  const auto evaluate = [&](const Target& t, float idepth, bool jac, ObservationResiduals* res) {
    ObservationInput in;
    in.camera = &camera;
    in.target = &t.kf->Pyramid();
    in.level = 0;
    in.R = t.R;
    in.t = t.t;
    in.idepth = idepth;
    in.host_affine = host.affine;
    in.target_affine = t.kf->affine;
    in.host_exposure = host.exposure;
    in.target_exposure = t.kf->exposure;
    return EvaluateObservation(patch, in, jac, res);
  };
  for (int it = 0; it < options.refine_iterations; ++it) {
    double H = 0.0, b = 0.0;
    for (const Target& t : ts) {
      ObservationResiduals res;
      if (!evaluate(t, rho, true, &res)) continue;
      const ErrorModel& model = t.kf->error_model;
      for (int k = 0; k < kPatternSize; ++k) {
        const double rw = std::sqrt(res.weight_g[k]) * res.r[k];
        const double w = res.weight_g[k] * model.Weight(rw);
        H += w * res.J_idepth(k) * res.J_idepth(k);
        b += w * res.J_idepth(k) * res.r[k];
      }
    }
    if (H < 1e-9) return false;
    const float step = static_cast<float>(-b / H);
    rho = std::max(1e-4f, rho + std::clamp(step, -0.5f * rho, 0.5f * rho));
    if (std::abs(step) < 1e-4f * rho) break;
  }
  out->idepth = rho;
  out->targets.clear();
  for (const Target& t : ts) {
    ObservationResiduals res;
    if (!evaluate(t, rho, false, &res)) continue;
    int good = 0;
    for (int k = 0; k < kPatternSize; ++k)
      good += !t.kf->error_model.IsOutlier(std::sqrt(res.weight_g[k]) * res.r[k]);
    if (good >= options.min_inlier_ratio * kPatternSize) out->targets.push_back(t.id);
  }
  return !out->targets.empty();
}

}  // namespace dsm
