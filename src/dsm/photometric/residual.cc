// SPDX-License-Identifier: MIT
#include "dsm/photometric/residual.h"

#include <cmath>

#include <Eigen/Geometry>

namespace dsm {

bool SampleHostPatch(const ImagePyramid& host, int level, const Eigen::Vector2f& center, HostPatch* patch) {
  patch->center = center;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = center.x() + kPattern[k][0], y = center.y() + kPattern[k][1];
    if (!host.InBounds(level, x, y, 1.f)) return false;
    const PixelGrad g = host.Sample(level, x, y);
    patch->value[k] = g[0];
    patch->weight_g[k] = GradientWeight(g[1] * g[1] + g[2] * g[2]);
  }
  return true;
}

bool EvaluateObservation(const HostPatch& host, const ObservationInput& in, Derivatives derivatives,
                         ObservationResiduals* out) {
  const PinholeCamera& cam = *in.camera;
  const float fx = static_cast<float>(cam.fx), fy = static_cast<float>(cam.fy);
  const float cx = static_cast<float>(cam.cx), cy = static_cast<float>(cam.cy);
  const float s = static_cast<float>(BrightnessRatio(in.host_affine, in.target_affine, in.host_exposure, in.target_exposure));
  const float b_h = static_cast<float>(in.host_affine.b), b_t = static_cast<float>(in.target_affine.b);
  const Eigen::Vector3f t_rho = in.t * in.idepth;
  {
    // The centre decides visibility and depth.
    const Eigen::Vector3f q((host.center.x() - cx) / fx, (host.center.y() - cy) / fy, 1.f);
    const Eigen::Vector3f p = in.R * q + t_rho;
    if (!(p.z() > 1e-6f * std::max(1.f, std::abs(in.idepth)))) return false;
    out->center_target = Eigen::Vector2f(fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy);
    out->target_depth = in.idepth > 0.f ? p.z() / in.idepth : 0.f;
  }
  for (int k = 0; k < kPatternSize; ++k) {
    const Eigen::Vector3f q((host.center.x() + kPattern[k][0] - cx) / fx, (host.center.y() + kPattern[k][1] - cy) / fy, 1.f);
    const Eigen::Vector3f p = in.R * q + t_rho;
    if (!(p.z() > 0.f)) return false;
    const float iz = 1.f / p.z();
    const float u = fx * p.x() * iz + cx, v = fy * p.y() * iz + cy;
    if (!in.target->InBounds(in.level, u, v, 2.f)) return false;
    const PixelGrad g = in.target->Sample(in.level, u, v);
    const float it_minus_b = g[0] - b_t;
    out->r[k] = (host.value[k] - b_h) - s * it_minus_b;
    out->weight_g[k] = 0.5f * (host.weight_g[k] + GradientWeight(g[1] * g[1] + g[2] * g[2]));
    if (derivatives == Derivatives::kNone) continue;
    // d r / d p = -s grad I_t^T J_pi
    const float dx = -s * g[1], dy = -s * g[2];
    const float Jp0 = dx * fx * iz, Jp1 = dy * fy * iz;
    const float Jp2 = -(dx * fx * p.x() + dy * fy * p.y()) * iz * iz;
    const Eigen::Vector3f dr_dp(Jp0, Jp1, Jp2);
    out->J_idepth(k) = dr_dp.dot(in.t);
    if (derivatives == Derivatives::kIdepth) continue;
    // d p / d xi = [rho I, -hat(p)]  ->  d r / d w = (p x dr_dp) ... = dr_dp^T (-hat(p)) = (p x dr_dp)^T
    out->J_pose.block<1, 3>(k, 0) = in.idepth * dr_dp.transpose();
    out->J_pose.block<1, 3>(k, 3) = p.cross(dr_dp).transpose();
    out->J_affine(k, 0) = -s * it_minus_b;
    out->J_affine(k, 1) = -1.f;
    out->J_affine(k, 2) = s * it_minus_b;
    out->J_affine(k, 3) = s;
  }
  return true;
}

}  // namespace dsm
