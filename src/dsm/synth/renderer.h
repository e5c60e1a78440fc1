// SPDX-License-Identifier: MIT
// Ray-casting renderer and image formation of the synthetic test world.
//
// RenderFrame casts one ray per pixel centre: albedo from the surface texture (filtered by the
// pixel footprint, see texture.h) and depth as z in the camera frame. The camera is an ideal
// pinhole, or a lens of any model camera.h reads (LensRays: each pixel's ray through the lens's
// distortion). FormImage then applies the photometric model
//   I(x) = gain * (exposure / 10 ms) * 255 * albedo(x) * V(x) + offset,
// optical blur, Gaussian noise and 8-bit quantisation.
#pragma once

#include <cstdint>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"
#include "dsm/lie/se3.h"
#include "dsm/synth/lens_rays.h"
#include "dsm/synth/scenes.h"

namespace dsm::synth {

// `depth` may be null. Pixels that see nothing get albedo 0 and depth 0. With `parallel`, rows are
// rendered with TBB (the result is identical).
void RenderFrame(const Scene& scene, const PinholeCamera& camera, const SE3d& world_from_cam, Image<float>* albedo,
                 Image<float>* depth, bool parallel = true);

// A rolling shutter: row v seen from row_world_from_cam[v] (one pose per row, the camera's at the
// row's exposure time).
void RenderRollingShutterFrame(const Scene& scene, const PinholeCamera& camera,
                               const std::vector<SE3d>& row_world_from_cam, Image<float>* albedo, Image<float>* depth,
                               bool parallel = true);

// The same through a lens.
void RenderFrame(const Scene& scene, const LensRays& lens, const SE3d& world_from_cam, Image<float>* albedo,
                 Image<float>* depth, bool parallel = true);
void RenderRollingShutterFrame(const Scene& scene, const LensRays& lens, const std::vector<SE3d>& row_world_from_cam,
                               Image<float>* albedo, Image<float>* depth, bool parallel = true);

// Radial vignette V = 1 - strength * (r / r_corner)^2, in (0, 1].
Image<float> MakeVignette(int width, int height, double strength);

struct FormationOptions {
  double noise_sigma = 0.0;
  double blur_sigma = 0.0;
  const Image<float>* vignette = nullptr;  // None when null.
  uint32_t noise_seed = 0;
};

Image<uint8_t> FormImage(const Image<float>& albedo, const Photometry& photometry, const FormationOptions& options);

// Frame i of a sequence through the full image formation (8-bit, as a camera gives it) returned as
// the float image a dataset reader yields, with its depth map.
struct RenderedFrame {
  Image<float> image;
  Image<float> depth;
};
RenderedFrame RenderSequenceFrame(const SynthSequence& sequence, size_t i, const FormationOptions& formation);

// Frame i's albedo and depth (may be null): through the sequence's lens or pinhole, with its
// rolling shutter or global.
void RenderSequenceAlbedo(const SynthSequence& sequence, size_t i, Image<float>* albedo, Image<float>* depth,
                          bool parallel = true);

}  // namespace dsm::synth
