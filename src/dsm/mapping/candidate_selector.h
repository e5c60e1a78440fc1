// SPDX-License-Identifier: MIT
// Candidate point selection (paper VI-C): well-spread pixels of locally high gradient.
//
// The image is split into 32 x 32 blocks; a block's threshold is the median of its gradient
// magnitudes plus a margin (smoothed over the neighbouring blocks). In each cell of a grid of
// `step` x `step` pixels, the pixel with the largest gradient above the threshold is taken; cells
// without one try the next pyramid levels with a lower threshold (so weakly textured areas still
// get some candidates). `step` adapts until the count is within 10% of the target.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/image/pyramid.h"

namespace dsm {

struct CandidateSelectorOptions {
  int target_count = 1500;
  float threshold_margin = 7.f;  // Added to the block median gradient, grey levels.
  int border = 4;                // Pixels left free at the image border.

  void Validate() const;
};

struct SelectedPixel {
  Eigen::Vector2f pixel;  // Level 0.
  float gradient = 0.f;   // |grad I|
};

std::vector<SelectedPixel> SelectCandidates(const ImagePyramid& image, const CandidateSelectorOptions& options,
                                            const Image<uint8_t>* valid_mask = nullptr);

}  // namespace dsm
