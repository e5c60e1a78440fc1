// SPDX-License-Identifier: MIT
#include "dsm/mapping/observation_check.h"

#include <cmath>

#include "dsm/photometric/residual.h"

namespace dsm {

namespace {

// The point's 8 residuals in `target` at level 0; false if the pattern leaves either image.
bool EvaluateAtLevel0(const Map& map, const PinholeCamera& camera, const Point& point, int target,
                      ObservationResiduals* res) {
  const Keyframe& host = map.keyframe(point.host);
  const Keyframe& t = map.keyframe(target);
  if (!point.patch_ok) return false;
  const SE3d target_from_host = t.cam_from_world * host.cam_from_world.Inverse();
  ObservationInput in;
  in.camera = &camera;
  in.target = &t.Pyramid();
  in.level = 0;
  in.R = target_from_host.Rotation().cast<float>();
  in.t = target_from_host.Translation().cast<float>();
  in.idepth = point.idepth;
  in.host_affine = host.affine;
  in.target_affine = t.affine;
  in.host_exposure = host.exposure;
  in.target_exposure = t.exposure;
  return EvaluateObservation(point.patch, in, Derivatives::kNone, res);
}

}  // namespace

bool LooksConsistent(const Map& map, const PinholeCamera& camera, const Point& point, int target,
                     const ErrorModel& model, double max_bad_ratio) {
  ObservationResiduals res;
  if (!EvaluateAtLevel0(map, camera, point, target, &res)) return false;
  int bad = 0;
  for (int k = 0; k < kPatternSize; ++k) bad += model.IsOutlier(std::sqrt(res.weight_g[k]) * res.r[k]);
  return bad <= max_bad_ratio * kPatternSize;
}

bool TextureGone(const Map& map, const PinholeCamera& camera, const Point& point, int target,
                 const TextureLossOptions& options) {
  ObservationResiduals res;
  return EvaluateAtLevel0(map, camera, point, target, &res) && TextureLost(point.patch, res, point.idepth, options);
}

}  // namespace dsm
