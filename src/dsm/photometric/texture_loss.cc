// SPDX-License-Identifier: MIT
#include "dsm/photometric/texture_loss.h"

#include "dsm/util/check.h"

namespace dsm {

void TextureLossOptions::Validate() const {
  if (!(max_variance_ratio >= 0.0 && max_variance_ratio < 1.0))
    throw InputError("the texture-loss ratio must be within [0, 1)");
  if (!(min_host_variance >= 0.0)) throw InputError("the texture-loss host variance must be non-negative");
  if (!(max_depth_ratio >= 1.0)) throw InputError("the texture-loss depth ratio must be at least 1");
}

bool TextureLost(const HostPatch& host, const ObservationResiduals& res, float idepth,
                 const TextureLossOptions& options) {
  if (!(options.max_variance_ratio > 0.0)) return false;
  const double ratio = res.target_depth * idepth;
  if (!(ratio <= options.max_depth_ratio && ratio * options.max_depth_ratio >= 1.0)) return false;
  PatternSamples target;  // In host units: I_h - r.
  for (int k = 0; k < kPatternSize; ++k) target[k] = host.value[k] - res.r[k];
  const float var_h = PatternVariance(host.value);
  return var_h >= options.min_host_variance && PatternVariance(target) < options.max_variance_ratio * var_h;
}

}  // namespace dsm
