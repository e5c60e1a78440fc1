// SPDX-License-Identifier: MIT
#include "dsm/optimization/pba_models.h"

#include <cstdint>

#include <tbb/parallel_for.h>

namespace dsm {

namespace {

std::vector<float> CameraResiduals(const std::vector<std::vector<std::vector<float>>>& residuals, size_t c) {
  std::vector<float> out;
  for (const auto& chunk : residuals) out.insert(out.end(), chunk[c].begin(), chunk[c].end());
  return out;
}

}  // namespace

std::vector<int> FitPbaModels(const std::vector<std::vector<std::vector<float>>>& residuals,
                              const std::vector<int>& cams, const std::vector<bool>& fixed, const PbaOptions& options,
                              std::vector<ErrorModel>* models) {
  std::vector<ErrorModel>& m = *models;
  if (options.refit_all_models) {
    std::vector<uint8_t> fitted(cams.size(), 0);
    tbb::parallel_for(size_t{0}, cams.size(), [&](size_t c) {
      const std::vector<float> r = CameraResiduals(residuals, c);
      m[c] = FitErrorModel(r, options.robust);
      fitted[c] = static_cast<int>(r.size()) >= options.robust.min_residuals;
    });
    if (options.max_sigma_ratio > 0) BoundErrorModelScales(options.max_sigma_ratio, fitted, models);
    std::vector<int> all(cams.size());
    for (size_t c = 0; c < cams.size(); ++c) all[c] = static_cast<int>(c);
    return all;
  }
  int newest = -1;
  for (size_t c = 0; c < cams.size(); ++c)
    if (!fixed[c] && (newest < 0 || cams[c] > cams[newest])) newest = static_cast<int>(c);
  if (newest < 0) return {};
  const std::vector<float> r = CameraResiduals(residuals, newest);
  if (static_cast<int>(r.size()) < options.robust.min_residuals) return {};
  m[newest] = FitErrorModel(r, options.robust);
  if (options.max_sigma_ratio > 0) {
    std::vector<uint8_t> fitted(cams.size(), 0);
    for (size_t c = 0; c < cams.size(); ++c) fitted[c] = m[c].fitted;
    CapErrorModelScale(ErrorModelScaleCap(options.max_sigma_ratio, fitted, m), &m[newest]);
  }
  return {newest};
}

}  // namespace dsm
