// SPDX-License-Identifier: MIT
#include "dsm/synth/texture.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "dsm/synth/smooth_step.h"

namespace dsm::synth {

namespace {

constexpr int kTileBits = 11;
constexpr int kTileSize = 1 << kTileBits;  // 2048 texels, periodic.
constexpr int kOctaves = 9;                // Wavelengths 1024, 512, ..., 4 texels.
constexpr float kOctaveGain = 0.92f;
constexpr int kMaskLevel = 7;  // Mip level of the weak-texture mask.

inline int FastFloor(float x) {
  const int i = static_cast<int>(x);
  return x < static_cast<float>(i) ? i - 1 : i;
}

// Periodic fractal value noise, baked once, with a box-filtered mip chain.
class NoiseTile {
 public:
  NoiseTile() {
    std::vector<float> base(kTileSize * kTileSize, 0.f);
    uint32_t state = 0x9E3779B9u;
    const auto next = [&state] {
      state ^= state << 13;  // xorshift32
      state ^= state >> 17;
      state ^= state << 5;
      return static_cast<float>(state & 0xFFFFFF) * (2.0f / 16777215.0f) - 1.0f;
    };
    float amplitude = 1.f, norm = 0.f;
    for (int k = 0; k < kOctaves; ++k) {
      const int cells = 2 << k;  // Lattice cells across the tile: wavelength 512 / cells texels.
      std::vector<float> lattice(cells * cells);
      for (float& v : lattice) v = next();
      const int texels_per_cell = kTileSize / cells;
      // Interpolation weights along one cell, shared by every cell and both axes.
      std::vector<float> weight(texels_per_cell);
      for (int i = 0; i < texels_per_cell; ++i) weight[i] = Fade(static_cast<float>(i) / texels_per_cell);
      for (int y = 0; y < kTileSize; ++y) {
        const int iy = y / texels_per_cell, y1 = (iy + 1) & (cells - 1);
        const float ty = weight[y % texels_per_cell];
        const float* row0 = &lattice[iy * cells];
        const float* row1 = &lattice[y1 * cells];
        float* out = &base[y * kTileSize];
        for (int ix = 0; ix < cells; ++ix) {
          const int x1 = (ix + 1) & (cells - 1);
          const float left = row0[ix] + (row1[ix] - row0[ix]) * ty;
          const float right = row0[x1] + (row1[x1] - row0[x1]) * ty;
          for (int i = 0; i < texels_per_cell; ++i) *out++ += amplitude * (left + (right - left) * weight[i]);
        }
      }
      norm += amplitude;
      amplitude *= kOctaveGain;
    }
    // Normalised to a standard deviation of about 0.5.
    double sum_sq = 0.0;
    for (float v : base) sum_sq += double(v) * v;
    const float scale = static_cast<float>(0.5 / std::sqrt(sum_sq / base.size()));
    for (float& v : base) v *= scale;
    (void)norm;
    levels_.push_back(std::move(base));
    for (int size = kTileSize / 2; size >= 1; size /= 2) {
      const std::vector<float>& fine = levels_.back();
      std::vector<float> coarse(size * size);
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
          coarse[y * size + x] = 0.25f * (fine[(2 * y) * 2 * size + 2 * x] + fine[(2 * y) * 2 * size + 2 * x + 1] +
                                          fine[(2 * y + 1) * 2 * size + 2 * x] + fine[(2 * y + 1) * 2 * size + 2 * x + 1]);
      levels_.push_back(std::move(coarse));
    }
    for (int l = 0; l <= kTileBits; ++l) {
      level_data_[l] = levels_[l].data();
      level_scale_[l] = std::ldexp(1.f, -l);
    }
  }

  // Bilinear sample of level L at level-0 texel coordinates (x, y), wrapping around.
  float Bilinear(int level, float x, float y) const {
    const int size = kTileSize >> level;
    const float s = level_scale_[level];  // 2^-level
    const float shift = 0.5f * s - 0.5f;  // Texel centres.
    const float lx = x * s + shift, ly = y * s + shift;
    const int ix = FastFloor(lx), iy = FastFloor(ly);
    const float tx = lx - ix, ty = ly - iy;
    const int mask = size - 1;
    const float* d = level_data_[level];
    const int x0 = ix & mask, x1 = (ix + 1) & mask, y0 = (iy & mask) * size, y1 = ((iy + 1) & mask) * size;
    const float top = d[y0 + x0] + (d[y0 + x1] - d[y0 + x0]) * tx;
    const float bottom = d[y1 + x0] + (d[y1 + x1] - d[y1 + x0]) * tx;
    return top + (bottom - top) * ty;
  }

  // Trilinear: level log2(footprint) between two mip levels.
  float Sample(float x, float y, float footprint) const {
    if (footprint <= 1.f) return Bilinear(0, x, y);
    // footprint = (1 + f) 2^e read from the float's bits: level e, blend f (~ the log2 fraction).
    uint32_t bits;
    std::memcpy(&bits, &footprint, sizeof(bits));
    const int level = static_cast<int>((bits >> 23) & 0xFF) - 127;
    const uint32_t mantissa_bits = (bits & 0x7FFFFFu) | 0x3F800000u;
    float mantissa;
    std::memcpy(&mantissa, &mantissa_bits, sizeof(mantissa));
    if (level >= kTileBits) return 0.f;
    const float a = Bilinear(level, x, y);
    const float b = Bilinear(level + 1, x, y);
    return a + (b - a) * (mantissa - 1.f);
  }

 private:
  std::vector<std::vector<float>> levels_;
  const float* level_data_[kTileBits + 1];
  float level_scale_[kTileBits + 1];
};

const NoiseTile& Tile() {
  static const NoiseTile tile;
  return tile;
}

// (cos, sin) of a turned texture's angle, 0.3 + 0.4 i / 255 rad for i = bits 23-30 of its seed.
struct Turn {
  float c, s;
};
const Turn& TurnOf(uint32_t seed) {
  static const std::vector<Turn> table = [] {
    std::vector<Turn> t(256);
    for (int i = 0; i < 256; ++i) {
      const double angle = 0.3 + 0.4 * i / 255.0;
      t[i] = {static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle))};
    }
    return t;
  }();
  return table[(seed >> 23) & 255u];
}

}  // namespace

float SampleNoiseTile(float x, float y, float footprint_texels) { return Tile().Sample(x, y, footprint_texels); }

float EvaluateTexture(const Texture& t, float u, float v, float footprint_m) {
  const NoiseTile& tile = Tile();
  // Tile coordinates (tu, tv) = R (u, v); the grid lines below stay on u and v.
  float tu = u, tv = v;
  if (t.turned) {
    const Turn& turn = TurnOf(t.seed);
    tu = turn.c * u - turn.s * v;
    tv = turn.s * u + turn.c * v;
  }
  // Texels per metre: the coarsest octave (1024 texels) spans scale_m.
  const float k = 1024.f / t.scale_m;
  // Per-texture offsets (in texels) decorrelate textures that share the tile.
  const float ox = static_cast<float>(t.seed & 2047u), oy = static_cast<float>((t.seed >> 11) & 2047u);
  const bool swap = (t.seed >> 22) & 1u;
  float pattern = swap ? tile.Sample(tv * k + ox, tu * k + oy, footprint_m * k)
                       : tile.Sample(tu * k + ox, tv * k + oy, footprint_m * k);
  if (t.line_spacing_m > 0.f) {
    // Lines of half-width w: distance to the nearest grid line, smoothed over ~1.5 px.
    const float w = 0.02f * t.line_spacing_m;
    const float su = u / t.line_spacing_m, sv = v / t.line_spacing_m;
    const float du = std::fabs(su - FastFloor(su + 0.5f)) * t.line_spacing_m;
    const float dv = std::fabs(sv - FastFloor(sv + 0.5f)) * t.line_spacing_m;
    const float soft = std::max(0.75f * footprint_m, 1e-4f);
    const float d = std::min(du, dv);
    if (d < w + soft) {
      const float line = 1.f - SmoothStep(w - soft, w + soft, d);
      // Lines thinner than a pixel blend into the average instead of aliasing.
      pattern -= 1.2f * line * SmoothStep(1.f, 3.f, 2.f * w / footprint_m);
    }
  }
  if (t.weak_fraction > 0.f) {
    // Slow mask (wavelengths of several metres): one bilinear lookup on a coarse mip level.
    const float m = 0.5f + 0.8f * tile.Bilinear(kMaskLevel, tu * 256.f + oy, tv * 256.f + ox);
    pattern *= 0.12f + 0.88f * SmoothStep(t.weak_fraction - 0.08f, t.weak_fraction + 0.08f, m);
  }
  return std::clamp(t.base + t.contrast * pattern, 0.02f, 0.98f);
}

}  // namespace dsm::synth
