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
//
// Pattern contrast: the centre's gradient says little about the 8-pixel pattern that the point's
// residuals compare (residual.h), and on a noisy image a strong gradient at one pixel is often
// the noise's. On path-traced frames such faint points bias the map, not merely blur it: the map
// adjusted from the true poses ends nearer them without the points of low pattern contrast c (the
// standard deviation of its 8 intensities), and not with a random share of points removed. So, when
// the system finds its first frame noisy (contrast_min_noise), no pixel is taken with
//   c < contrast_factor * sigma,
// sigma the image's noise level (the median of its blocks'; pure noise gives c = 0.94 sigma, and
// c > 2 sigma with probability 4e-5): the signal's variance must exceed contrast_factor^2 - 1
// times the noise's. Not each block's own sigma: a textured block's estimate grows with its
// texture. Not on clean images: there faint points carried information (the synthetic scenes
// were worse with the floor). A cell whose pick fails stays empty, and the step adapts to the
// cells with a pick, so the grid does not grow denser elsewhere instead.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/image/pyramid.h"

namespace dsm {

struct CandidateSelectorOptions {
  int target_count = 1500;
  float threshold_margin = 7.f;  // Added to the block median gradient, grey levels.
  float noise_factor = 4.f;      // Gradient floor in standard deviations of the noise's gradient.
  float contrast_factor = 3.f;      // Pattern contrast floor in noise sigmas (0: none) ...
  static constexpr float contrast_min_noise = 2.5f;  // ... set when the first frame's noise reaches this (System).
  static constexpr int border = 4;              // Pixels left free at the image border.

  void Validate() const;
};

struct SelectedPixel {
  Eigen::Vector2f pixel;  // Level 0.
  float gradient = 0.f;   // |grad I|
};

// Per 32 x 32 block (smoothed over the 3 x 3 neighbouring blocks): the selection threshold, the
// noise floor every selected gradient exceeds, and the estimated noise sigma (grey levels); and
// the floor of the pattern contrast, from the image's noise level.
struct BlockThresholds {
  Image<float> select, floor, noise_sigma;
  float contrast = 0.f;
};

// Standard deviation of the 8 pattern intensities around (x, y); the pattern must lie inside.
float PatternContrast(const Image<float>& value, int x, int y);
BlockThresholds ComputeBlockThresholds(const ImagePyramid& image, const CandidateSelectorOptions& options);

std::vector<SelectedPixel> SelectCandidates(const ImagePyramid& image, const CandidateSelectorOptions& options,
                                            const Image<uint8_t>* valid_mask = nullptr);

}  // namespace dsm
