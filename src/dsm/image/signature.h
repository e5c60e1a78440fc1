// SPDX-License-Identifier: MIT
// A compact global description of a frame, for the quality test and for relocalisation.
//
// texture: mean gradient magnitude at pyramid level 1, |dI/dx| + |dI/dy| by central differences
//   (grey levels per level-1 pixel): a black, saturated or covered frame has almost none.
// thumbnail: the coarsest level (about 47 x 30 for 752 x 480 and five levels) smoothed by a 3 x 3
//   binomial, made zero-mean and of unit norm, as PTAM's small blurry images: the similarity of two
//   frames is the dot product of their thumbnails (their normalised cross-correlation, in [-1, 1]),
//   blind to brightness and contrast changes.
// mean, deviation: of the smoothed coarsest level (grey levels): of two views of one scene,
//   I_a ~ e^alpha I_b + beta with alpha = log(deviation_a / deviation_b), beta = mean_a - e^alpha
//   mean_b (ImageBrightness), a guess of the brightness change that needs no history.
#pragma once

#include <vector>

#include "dsm/image/pyramid.h"

namespace dsm {

struct FrameSignature {
  double texture = 0.0;
  double mean = 0.0, deviation = 0.0;
  int width = 0, height = 0;
  std::vector<float> thumbnail;  // Row-major, width x height; empty for a uniform image.
};

FrameSignature ComputeSignature(const ImagePyramid& pyramid);

// Normalised cross-correlation of the two thumbnails; -1 when either is empty or the sizes differ.
double Similarity(const FrameSignature& a, const FrameSignature& b);

// The brightness change (alpha, beta) from b's image to a's as their statistics say (see above);
// false when either is uniform.
bool ImageBrightness(const FrameSignature& a, const FrameSignature& b, double* alpha, double* beta);

}  // namespace dsm
