// SPDX-License-Identifier: MIT
#include "dsm/mapping/keyframe_decision.h"

#include "dsm/util/check.h"

namespace dsm {

void KeyframeOptions::Validate() const {
  if (!(weight_parallax >= 0 && weight_visibility >= 0 && weight_brightness >= 0))
    throw InputError("keyframe weights must be non-negative");
}

bool ShouldCreateKeyframe(const KeyframeScores& s, const KeyframeOptions& o) {
  const double score = o.weight_parallax * s.parallax + o.weight_visibility * (1.0 - s.visibility) +
                       o.weight_brightness * s.brightness;
  if (score > 1.0) return true;
  return s.first_rmse > 0.0 && s.rmse > o.residual_growth * s.first_rmse;
}

}  // namespace dsm
