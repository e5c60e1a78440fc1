// SPDX-License-Identifier: MIT
// Has a point's texture vanished in a target keyframe? A point is selected where its host image
// has texture; seen in a target through a nearer textureless surface (a plain pillar, wall or
// door passing in front of it) its pattern lands on a flat patch that shows little beyond noise.
// Such an observation carries no information (the target's gradient, which every Jacobian
// multiplies, is noise), yet its residuals, about the host pattern's own contrast, widen the
// target keyframe's fitted error model: the inlier threshold grows and with it what the pixel
// masks let through, wherever a near occluder sweeps through the window.
//
// The target's samples in host units, through the affine brightness model, are
//   s (I_t[u'_k] - b_t) + b_h = I_h[u_k] - r_k,
// so the pattern's variances need no other samples:
//   V_h = Var_k(I_h[u_k]),   V_t = Var_k(I_h[u_k] - r_k).
// The texture is lost when the host shows texture (V_h >= min_host_variance) and the target keeps
// less than a share of it:  V_t < max_variance_ratio V_h.
// A surface seen from farther away than its host saw it shows the same texture compressed into
// fewer pixels (less variance in 8 samples, by the sampling's blur); seen from nearer, the 8
// samples cover a smaller part of it (less variance where the texture is smooth, as when walking
// down a corridor). The test is only made when the point's depth in the target is within a
// factor max_depth_ratio of its depth in the host (the pattern centre's, 1 / rho).
#pragma once

#include "dsm/photometric/residual.h"

namespace dsm {

// The share of the host's pattern variance below which a target has lost the texture. The test
// is off by default; SystemOptions::texture_loss_min_noise turns it on for noisy images.
constexpr double kTextureLossRatio = 0.25;

struct TextureLossOptions {
  double max_variance_ratio = 0.0;   // 0: the test is off; kTextureLossRatio to use it.
  double min_host_variance = 25.0;   // Grey levels^2.
  double max_depth_ratio = 1.25;     // Target depth over host depth.

  void Validate() const;  // Throws InputError naming the option.
};

// `idepth`: the point's inverse depth in its host; `res`: the observation evaluated at it.
bool TextureLost(const HostPatch& host, const ObservationResiduals& res, float idepth,
                 const TextureLossOptions& options);

}  // namespace dsm
