// SPDX-License-Identifier: MIT
// Which map points does a keyframe not see because a nearer surface covers them? The window's
// points are projected into the keyframe and binned into cells of `cell_px`; a point is hidden
// when at least `min_occluders` points in its cell and the eight around it are nearer by more
// than the factor `depth_ratio` in inverse depth:
//   occluded(p)  <=>  #{ q in the 3 x 3 cells around p : rho_q > depth_ratio * rho_p } >= min_occluders
// Two occluders rather than one, so that a single point with a wrong depth hides nothing. A
// point close to an occluder's silhouette counts as hidden too: its pattern straddles the edge.
// A near surface without texture (a plain pillar, a door) holds points only along its silhouette,
// so its inside hides nothing by that test; the PBA's outlier test and error models handle what
// it lets through. Observations created for hidden points would only feed the error model with occlusion
// residuals (the PBA rejects them later, but a keyframe whose view is mostly covered by a near
// object fits its inlier threshold to them).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace dsm {

struct OcclusionOptions {
  bool enabled = true;  // false: every point that projects into the keyframe is observed there.
  static constexpr int cell_px = 8;
  float depth_ratio = 1.3f;
  static constexpr int min_occluders = 2;
  void Validate() const;
};

class OcclusionGrid {
 public:
  OcclusionGrid(int width, int height, const OcclusionOptions& options);
  void Add(const Eigen::Vector2f& pixel, float idepth);  // A point seen at `pixel` with inverse depth `idepth`.
  bool IsOccluded(const Eigen::Vector2f& pixel, float idepth) const;

 private:
  int Cell(float x, float y) const;
  OcclusionOptions options_;
  int cols_, rows_;
  std::vector<std::vector<float>> cells_;  // Inverse depths per cell.
};

}  // namespace dsm
