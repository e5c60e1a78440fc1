// SPDX-License-Identifier: MIT
// Image noise: its level, estimated from one image.
//
// Noise level (Immerkaer 1996): the kernel N = [1 -2 1; -2 4 -2; 1 -2 1] annihilates constant and
// linear intensity (and most smooth shading), so where there is no strong edge its response is
// image noise, with standard deviation 6 sigma (sum of N's squared entries: 36). Per block of
// 32 x 32 pixels, sigma = median |N * I| / (6 * 0.6745) (the median of a half-normal is 0.6745
// sigma, and the median ignores the block's few edges); the image's level is the median over
// its blocks.
//
// The level decides how the system treats a recording's images (MappingSide::ChooseNoiseHandling):
// camera images have 0.3-2 grey levels, path-traced renders with few samples 3-6.
#pragma once

#include "dsm/image/image.h"

namespace dsm {

constexpr int kNoiseBlock = 32;

// The noise sigma of the block at (bx, by) (kNoiseBlock pixels; the last ones may be smaller), 0
// for a block without interior pixels.
float BlockNoiseSigma(const Image<float>& image, int bx, int by);

// The image's noise sigma, grey levels: the median of its blocks' (see above).
float EstimateNoiseSigma(const Image<float>& image);

}  // namespace dsm
