// SPDX-License-Identifier: MIT
// Candidate point selection (paper VI-C): well-spread pixels of locally high gradient.
//
// The image is split into 32 x 32 blocks; a block's threshold is the median of its gradient
// magnitudes plus a margin (smoothed over the neighbouring blocks). In each cell of a grid of
// `step` x `step` pixels, the pixel with the largest gradient above the threshold is taken; every
// other cell without one takes its largest gradient above half the threshold (so weakly textured
// areas still get some candidates). `step` adapts until the count is within 10% of the target.
//
// Image noise: a pixel whose gradient noise alone could make carries no depth (its epipolar match
// is a coin toss, its residuals pull poses at random). Each block's noise sigma is estimated from
// the median response of a kernel that annihilates smooth intensity (image/noise.h), and no pixel
// is taken below noise_factor * sigma / sqrt(2), the noise's gradient at that many standard
// deviations. On clean images (sigma ~ 1) this floor lies below both thresholds and changes
// nothing; on render noise or a dark, noisy sensor it keeps the selection off flat areas.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/image/pyramid.h"

namespace dsm {

struct CandidateSelectorOptions {
  int target_count = 1500;
  float threshold_margin = 7.f;  // Added to the block median gradient, grey levels.
  float noise_factor = 4.f;      // Gradient floor in standard deviations of the noise's gradient.
  int border = 4;                // Pixels left free at the image border.
  // Gradient noise over sigma_estimated / sqrt(2): 1 for unsmoothed frames; the system sets
  // SmoothedGradientNoiseGain (image/noise.h) when it smooths them.
  double noise_gradient_gain = 1.0;

  void Validate() const;
};

struct SelectedPixel {
  Eigen::Vector2f pixel;  // Level 0.
  float gradient = 0.f;   // |grad I|
};

// Per 32 x 32 block (smoothed over the 3 x 3 neighbouring blocks): the selection threshold, the
// noise floor every selected gradient exceeds, and the estimated noise sigma (grey levels).
struct BlockThresholds {
  Image<float> select, floor, noise_sigma;
};
BlockThresholds ComputeBlockThresholds(const ImagePyramid& image, const CandidateSelectorOptions& options);

std::vector<SelectedPixel> SelectCandidates(const ImagePyramid& image, const CandidateSelectorOptions& options,
                                            const Image<uint8_t>* valid_mask = nullptr);

}  // namespace dsm
