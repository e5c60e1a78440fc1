// SPDX-License-Identifier: MIT
#include "dsm/photometric/residual.h"

#include <cmath>

#include <Eigen/Geometry>

namespace dsm {

bool SampleHostPatch(const ImagePyramid& host, int level, const Eigen::Vector2f& center, Interpolation interpolation,
                     HostPatch* patch) {
  patch->center = center;
  patch->interpolation = interpolation;
  const bool bspline = interpolation == Interpolation::kBSpline;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = center.x() + kPattern[k][0], y = center.y() + kPattern[k][1];
    if (!host.InBounds(level, x, y, bspline ? 2.f : 1.f)) return false;
    // The gradient weight is the stored gradient's (central differences), either way.
    const PixelGrad g = host.Sample(level, x, y);
    patch->value[k] = bspline ? host.SampleBSpline(level, x, y)[0] : g[0];
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
  // Lane-wise over the 8 pattern pixels (vectorised): projection, then the samples (gathered),
  // then residuals, weights and Jacobians.
  constexpr int n = kPatternSize;
  alignas(32) float px[n], py[n], pz[n], iz[n], u[n], v[n], value[n], gx[n], gy[n];
  const float R00 = in.R(0, 0), R01 = in.R(0, 1), R02 = in.R(0, 2), R10 = in.R(1, 0), R11 = in.R(1, 1),
              R12 = in.R(1, 2), R20 = in.R(2, 0), R21 = in.R(2, 1), R22 = in.R(2, 2);
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    // p = R q_k + t rho,  q_k = K^-1 (u_k, 1)
    const float qx = (host.center.x() + static_cast<float>(kPattern[k][0]) - cx) / fx;
    const float qy = (host.center.y() + static_cast<float>(kPattern[k][1]) - cy) / fy;
    px[k] = R00 * qx + (R01 * qy + R02) + t_rho.x();
    py[k] = R10 * qx + (R11 * qy + R12) + t_rho.y();
    pz[k] = R20 * qx + (R21 * qy + R22) + t_rho.z();
    iz[k] = 1.f / pz[k];
    u[k] = fx * px[k] * iz[k] + cx;
    v[k] = fy * py[k] * iz[k] + cy;
  }
  for (int k = 0; k < n; ++k) {
    if (!(pz[k] > 0.f) || !in.target->InBounds(in.level, u[k], v[k], 2.f)) return false;
  }
  if (host.interpolation == Interpolation::kBSpline) {
    // The noise of bilinear samples: with independent pixel noise of variance sigma^2 a sample at
    // fraction (f, g) has variance sigma^2 c(f) c(g), c(f) = (1 - f)^2 + f^2, from sigma^2 at a
    // pixel to sigma^2 / 4 half-way; E[r^2] carries s^2 sigma^2 c(f) c(g), a ripple that draws
    // each pattern pixel towards the middle between four pixels. The B-spline's squared weights
    // sum to 0.25 .. 0.21: no ripple to speak of. Its derivatives are the energy's own.
    for (int k = 0; k < n; ++k) {
      const PixelGrad g = in.target->SampleBSpline(in.level, u[k], v[k]);
      value[k] = g[0];
      gx[k] = g[1];
      gy[k] = g[2];
    }
  } else {
    in.target->Sample8(in.level, u, v, value, gx, gy);
  }
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    const float it_minus_b = value[k] - b_t;
    out->r[k] = (host.value[k] - b_h) - s * it_minus_b;
    out->weight_g[k] = 0.5f * (host.weight_g[k] + GradientWeight(gx[k] * gx[k] + gy[k] * gy[k]));
  }
  if (derivatives == Derivatives::kNone) return true;
  const float tx = in.t.x(), ty = in.t.y(), tz = in.t.z();
  alignas(32) float Jp0[n], Jp1[n], Jp2[n];  // d r / d p
  float* J_idepth = out->J_idepth.data();
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    // d r / d p = -s grad I_t^T J_pi
    const float dx = -s * gx[k], dy = -s * gy[k];
    Jp0[k] = dx * fx * iz[k];
    Jp1[k] = dy * fy * iz[k];
    Jp2[k] = -(dx * fx * px[k] + dy * fy * py[k]) * iz[k] * iz[k];
    J_idepth[k] = Jp0[k] * tx + (Jp1[k] * ty + Jp2[k] * tz);
  }
  if (derivatives == Derivatives::kIdepth) return true;
  float* Jx = out->J_pose.data();  // Column-major: column j at Jx + j n.
  float* Ja = out->J_affine.data();
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    // d p / d xi = [rho I, -hat(p)]  ->  d r / d w = dr_dp^T (-hat(p)) = (p x dr_dp)^T
    Jx[k] = in.idepth * Jp0[k];
    Jx[n + k] = in.idepth * Jp1[k];
    Jx[2 * n + k] = in.idepth * Jp2[k];
    Jx[3 * n + k] = py[k] * Jp2[k] - pz[k] * Jp1[k];
    Jx[4 * n + k] = pz[k] * Jp0[k] - px[k] * Jp2[k];
    Jx[5 * n + k] = px[k] * Jp1[k] - py[k] * Jp0[k];
    const float it_minus_b = value[k] - b_t;
    Ja[k] = -s * it_minus_b;
    Ja[n + k] = -1.f;
    Ja[2 * n + k] = s * it_minus_b;
    Ja[3 * n + k] = s;
  }
  return true;
}

}  // namespace dsm
