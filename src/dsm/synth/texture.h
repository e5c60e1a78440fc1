// SPDX-License-Identifier: MIT
// Procedural, band-limited surface textures: albedo as a function of surface coordinates (u, v) in
// metres and the pixel footprint (metres per pixel on the surface).
//
//   albedo = base + contrast * mask(R uv) * (F(1024 R uv / s + o) + lines(uv))
//
// F is a periodic fractal noise tile (2048 texels, nine octaves with wavelengths 1024 .. 4 texels,
// i.e. s .. s / 256 on the surface, 0.92 gain per octave) sampled from a mip-mapped table with
// trilinear filtering at the pixel footprint, so the image is band-limited: no aliasing, and any
// view of a point sees nearly the same intensity — what the photometric constancy of direct
// methods assumes. `mask` is a slow variation that leaves weakly textured patches.
//
// R is the identity by default: the surface then repeats every 2 s along u and v, so a camera
// moving down a long corridor sees the same floor and walls again every 2 s, and a lost frame may
// relocalise a whole number of periods away. A `turned` texture reads the tile along axes turned
// by its own angle in [0.3, 0.7] rad (from its seed): the lattice of repeats then has no short
// vector along u, v or a diagonal.
#pragma once

#include <cstdint>

namespace dsm::synth {

struct Texture {
  uint32_t seed = 1;
  float base = 0.5f;         // Mean albedo, in (0, 1).
  float contrast = 0.3f;     // Amplitude of the pattern.
  float scale_m = 1.0f;      // Wavelength of the coarsest octave.
  float line_spacing_m = 0;  // > 0 adds dark grid lines (tiles, panels) with sharp edges.
  float weak_fraction = 0;   // Share of the surface (0..1) where the texture fades to almost flat.
  bool turned = false;       // Tile read along turned axes: no repeats along u and v (see above).
};

// Albedo in [0.02, 0.98] at (u, v) seen with `footprint_m` metres per pixel.
float EvaluateTexture(const Texture& texture, float u, float v, float footprint_m);

// The fractal tile F at texel coordinates (x, y) (period 2048), filtered over `footprint` texels;
// values have zero mean and are roughly within [-1, 1].
float SampleNoiseTile(float x, float y, float footprint_texels);

}  // namespace dsm::synth
