// SPDX-License-Identifier: MIT
// The error models of one photometric bundle adjustment (pba.h), fitted to its residuals.
//
// With pba.refit_all_models every camera's model is fitted to the residuals observed in it, in
// parallel, and each fitted scale is bounded by max_sigma_ratio times the median scale (see pba.h
// on why). Otherwise only the newest free camera's model is fitted (kept when it has too few
// residuals), as the original DSM does, and bounded by the median over the problem's fitted models.
#pragma once

#include <vector>

#include "dsm/optimization/pba.h"
#include "dsm/photometric/robust.h"

namespace dsm {

// residuals[chunk][camera]: the residuals observed in each camera, concatenated over the chunks in
// order. cams: keyframe ids; fixed: per camera. Returns the camera indices whose model was fitted.
std::vector<int> FitPbaModels(const std::vector<std::vector<std::vector<float>>>& residuals,
                              const std::vector<int>& cams, const std::vector<bool>& fixed, const PbaOptions& options,
                              std::vector<ErrorModel>* models);

}  // namespace dsm
