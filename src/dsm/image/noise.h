// SPDX-License-Identifier: MIT
// Image noise: its level, estimated from one image, and the Gaussian smoothing that tempers it.
//
// Noise level (Immerkaer 1996): the kernel N = [1 -2 1; -2 4 -2; 1 -2 1] annihilates constant and
// linear intensity (and most smooth shading), so where there is no strong edge its response is
// image noise, with standard deviation 6 sigma (sum of N's squared entries: 36). Per block of
// 32 x 32 pixels, sigma = median |N * I| / (6 * 0.6745) (the median of a half-normal is 0.6745
// sigma, and the median ignores the block's few edges); the image's level is the median over
// its blocks.
//
// Why smooth: a residual samples its target image bilinearly between pixels. With independent
// pixel noise of variance s^2 the sample's noise variance is
//   s^2 ((1 - fx)^2 + fx^2) ((1 - fy)^2 + fy^2),     (fx, fy) the sub-pixel position,
// a quarter of it half-way between pixels: the energy is lower there whatever the geometry, a
// ripple of period one pixel that pulls every inverse depth and pose. On a clean camera image
// (s ~ 1 grey level) the ripple is far below the photometric signal; on render noise (path
// tracing with few samples: s ~ 3-6) it is as large as the signal of a 0.3 px misalignment.
// A Gaussian of 0.7 px correlates neighbouring pixels, so interpolation no longer averages the
// noise down, and lowers the noise itself to ~0.4 s.
#pragma once

#include "dsm/image/image.h"

namespace dsm {

constexpr int kNoiseBlock = 32;

// The noise sigma of the block at (bx, by) (kNoiseBlock pixels; the last ones may be smaller), 0
// for a block without interior pixels.
float BlockNoiseSigma(const Image<float>& image, int bx, int by);

// The image's noise sigma, grey levels: the median of its blocks' (see above).
float EstimateNoiseSigma(const Image<float>& image);

// Convolution with the normalised 1-D Gaussian of `sigma` pixels (truncated at 3 sigma, at least
// 3 taps) along rows and columns, the border pixels repeated; sigma <= 0 returns a copy.
Image<float> GaussianSmooth(const Image<float>& image, float sigma);

// Smoothing correlates the noise, and the noise level estimated afterwards no longer predicts the
// noise of a gradient. For independent noise s smoothed by G (the 2-D kernel of `sigma`), a
// central-difference gradient component has standard deviation s |D * G| (D = [1/2 0 -1/2]) and
// the estimate above gives s |N * G| / 6; on an unsmoothed image they are s / sqrt(2) and s.
// Returns the factor that turns sigma_estimated / sqrt(2) into the gradient noise:
//   |D * G| / (|N * G| / (6 sqrt(2)))       (1 for sigma <= 0; 3.5 for 0.7 px).
double SmoothedGradientNoiseGain(float sigma);

// The same for an intensity: its noise is s |G|, so the factor that turns sigma_estimated into it
// is |G| / (|N * G| / 6) (1 for sigma <= 0).
double SmoothedValueNoiseGain(float sigma);

}  // namespace dsm
