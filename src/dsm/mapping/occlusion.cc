// SPDX-License-Identifier: MIT
#include "dsm/mapping/occlusion.h"

#include <algorithm>

#include "dsm/util/check.h"

namespace dsm {

void OcclusionOptions::Validate() const {
  if (!(depth_ratio > 1.f)) throw InputError("occlusion.depth_ratio must be above 1");
}

OcclusionGrid::OcclusionGrid(int width, int height, const OcclusionOptions& options)
    : options_(options),
      cols_((width + options.cell_px - 1) / options.cell_px),
      rows_((height + options.cell_px - 1) / options.cell_px),
      cells_(static_cast<size_t>(cols_) * rows_) {}

int OcclusionGrid::Cell(float x, float y) const {
  const int cx = static_cast<int>(x) / options_.cell_px, cy = static_cast<int>(y) / options_.cell_px;
  if (x < 0.f || y < 0.f || cx >= cols_ || cy >= rows_) return -1;
  return cy * cols_ + cx;
}

void OcclusionGrid::Add(const Eigen::Vector2f& pixel, float idepth) {
  const int c = Cell(pixel.x(), pixel.y());
  if (c >= 0) cells_[c].push_back(idepth);
}

bool OcclusionGrid::IsOccluded(const Eigen::Vector2f& pixel, float idepth) const {
  const int c = Cell(pixel.x(), pixel.y());
  if (c < 0 || !options_.enabled) return false;
  const int cx = c % cols_, cy = c / cols_;
  const float nearer = options_.depth_ratio * idepth;
  int count = 0;
  for (int y = std::max(0, cy - 1); y <= std::min(rows_ - 1, cy + 1); ++y)
    for (int x = std::max(0, cx - 1); x <= std::min(cols_ - 1, cx + 1); ++x)
      for (float rho : cells_[static_cast<size_t>(y) * cols_ + x]) count += rho > nearer;
  return count >= options_.min_occluders;
}

}  // namespace dsm
