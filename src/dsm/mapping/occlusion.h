// SPDX-License-Identifier: MIT
// Which map points does a keyframe not see because a nearer surface covers them? The window's
// points are projected into the keyframe and binned into cells of `cell_px`; a point is hidden
// when at least `min_occluders` points in its cell and the eight around it are nearer by more
// than the factor `depth_ratio` in inverse depth:
//   occluded(p)  <=>  #{ q in the 3 x 3 cells around p : rho_q > depth_ratio * rho_p } >= min_occluders
// Two occluders rather than one, so that a single point with a wrong depth hides nothing. A
// point close to an occluder's silhouette counts as hidden too: its pattern straddles the edge.
// A near surface without texture (a plain pillar, a door) holds points only along its silhouette,
// so its inside hides nothing by that test. `IsBetween` tells when a point lies between nearer
// points on two opposite sides, left and right or above and below, within `span_px` along the
// band of 3 cells through it:
//   between(p)  <=>  (n_left >= m and n_right >= m) or (n_up >= m and n_down >= m),  m = min_occluders
// where n_left counts the points nearer than p by `depth_ratio` in the cells 1 .. span_px / cell_px
// to the left of p's cell, in p's row of cells and the rows above and below (likewise the others).
// That is no proof: looking down a corridor or into a room's corner, the far points lie between
// nearer walls and are seen. `texture_check` says when the image is asked instead: a point whose
// texture is gone in the new keyframe (texture_loss.h, at the tracked pose) is hidden there
//   "none": never (the default), "between": when it is also between nearer points, "all": always.
// Observations created for hidden points would only feed the error model with occlusion
// residuals (the PBA rejects them later, but a keyframe whose view is mostly covered by a near
// object fits its inlier threshold to them).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dsm {

struct OcclusionOptions {
  bool enabled = true;  // false: every point that projects into the keyframe is observed there.
  int cell_px = 8;
  float depth_ratio = 1.3f;
  int min_occluders = 2;
  int span_px = 96;  // IsBetween's reach on each side.
  std::string texture_check = "none";  // none | between | all (see above).
  // > 0: the window's candidates whose inverse-depth interval is at most this share of their
  // inverse depth count as occluders too (System::AddCandidatesToOcclusionGrid); 0: map points only.
  float candidate_interval = 0.f;
  void Validate() const;
};

class OcclusionGrid {
 public:
  OcclusionGrid(int width, int height, const OcclusionOptions& options);
  void Add(const Eigen::Vector2f& pixel, float idepth);  // A point seen at `pixel` with inverse depth `idepth`.
  bool IsOccluded(const Eigen::Vector2f& pixel, float idepth) const;
  bool IsBetween(const Eigen::Vector2f& pixel, float idepth) const;

 private:
  int Cell(float x, float y) const;
  // Nearer points than `nearer` in the band of 3 cells (across the direction (dx, dy)) at steps
  // 1 .. span_px / cell_px from cell (cx, cy), counted until `enough`.
  int CountAlong(int cx, int cy, int dx, int dy, float nearer, int enough) const;
  OcclusionOptions options_;
  int cols_, rows_;
  std::vector<std::vector<float>> cells_;  // Inverse depths per cell.
};

}  // namespace dsm
