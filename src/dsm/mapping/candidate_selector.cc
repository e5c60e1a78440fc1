// SPDX-License-Identifier: MIT
#include "dsm/mapping/candidate_selector.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "dsm/image/noise.h"
#include "dsm/photometric/residual.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {

void CandidateSelectorOptions::Validate() const {
  if (target_count < 10 || target_count > 100000) throw InputError("candidates.target_count must be within 10..100000");
  if (!(threshold_margin >= 0)) throw InputError("candidates.threshold_margin must be non-negative");
  if (!(noise_factor >= 0)) throw InputError("candidates.noise_factor must be non-negative");
  if (!(contrast_factor >= 0)) throw InputError("candidates.contrast_factor must be non-negative");
}

namespace {

constexpr int kBlock = kNoiseBlock;

// Per level-0 pixel: its intensity and its gradient magnitude |grad I| (rows in parallel).
struct Level0 {
  Image<float> value, gradient;
};
Level0 ReadLevel0(const ImagePyramid& image) {
  const int w = image.width(0), h = image.height(0);
  Level0 out{Image<float>(w, h), Image<float>(w, h)};
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      out.value(x, y) = image.Value(0, x, y);
      out.gradient(x, y) = image.At(0, x, y).tail<2>().norm();
    }
  });
  return out;
}

// Averages each block's value with its 3 x 3 neighbouring blocks.
Image<float> SmoothBlocks(const Image<float>& raw) {
  Image<float> smooth(raw.width(), raw.height());
  for (int by = 0; by < raw.height(); ++by)
    for (int bx = 0; bx < raw.width(); ++bx) {
      float sum = 0.f;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = bx + dx, y = by + dy;
          if (x < 0 || y < 0 || x >= raw.width() || y >= raw.height()) continue;
          sum += raw(x, y);
          ++n;
        }
      smooth(bx, by) = sum / n;
    }
  return smooth;
}

BlockThresholds BlockThresholdsOf(const Level0& image, const CandidateSelectorOptions& options) {
  const int w = image.value.width(), h = image.value.height();
  const int bw = (w + kBlock - 1) / kBlock, bh = (h + kBlock - 1) / kBlock;
  Image<float> select(bw, bh), noise(bw, bh);
  // Rows of blocks in parallel (each block on its own).
  tbb::parallel_for(0, bh, [&](int by) {
    std::vector<float> g;
    for (int bx = 0; bx < bw; ++bx) {
      g.clear();
      for (int y = by * kBlock; y < std::min(h, (by + 1) * kBlock); ++y)
        for (int x = bx * kBlock; x < std::min(w, (bx + 1) * kBlock); ++x) g.push_back(image.gradient(x, y));
      select(bx, by) = Median(g) + options.threshold_margin;
      noise(bx, by) = BlockNoiseSigma(image.value, bx, by);
    }
  });
  BlockThresholds t;
  t.noise_sigma = SmoothBlocks(noise);
  // The image's noise level (noise.h: the median over its blocks) sets the contrast floor: a
  // block's own estimate grows with its texture, which leaks into the kernel's response.
  std::vector<float> sigmas(noise.data(), noise.data() + noise.size());
  t.contrast = options.contrast_factor * (sigmas.empty() ? 0.f : Median(sigmas));
  t.select = SmoothBlocks(select);
  // Each gradient component (a central difference, (I(x+1) - I(x-1)) / 2) of pure noise has
  // standard deviation sigma / sqrt(2); its magnitude exceeds k sigma / sqrt(2) with probability
  // exp(-k^2 / 2) (Rayleigh): 0.03% for k = 4.
  t.floor = Image<float>(bw, bh);
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      t.floor(bx, by) = options.noise_factor * t.noise_sigma(bx, by) / std::sqrt(2.f);
      t.select(bx, by) = std::max(t.select(bx, by), t.floor(bx, by));
    }
  return t;
}

// One pick per cell of `step` x `step` pixels; `cells` counts the cells with a pick, kept or not.
std::vector<SelectedPixel> SelectWithStep(const Level0& image, const BlockThresholds& thresholds, int step,
                                          int border, const Image<uint8_t>* mask, int* cells) {
  std::vector<SelectedPixel> out;
  const Image<float>& gradient = image.gradient;
  const int w = gradient.width(), h = gradient.height();
  // A cell's pick without pattern contrast leaves the cell empty: neither a weaker pixel of the
  // cell (whose gradient is the noise's all the more) nor a denser grid elsewhere takes its place.
  auto has_contrast = [&](const Eigen::Vector2f& px) {
    const int x = static_cast<int>(px.x()), y = static_cast<int>(px.y());
    return thresholds.contrast <= 0.f || PatternContrast(image.value, x, y) >= thresholds.contrast;
  };
  *cells = 0;
  for (int cy = border; cy < h - border; cy += step) {
    for (int cx = border; cx < w - border; cx += step) {
      // Level 0: the strongest pixel above its block threshold; else a weaker one (coarser detail).
      float best = 0.f, best_weak = 0.f;
      Eigen::Vector2f best_px = Eigen::Vector2f::Zero(), weak_px = Eigen::Vector2f::Zero();
      for (int y = cy; y < std::min(cy + step, h - border); ++y) {
        for (int x = cx; x < std::min(cx + step, w - border); ++x) {
          if (mask && !(*mask)(x, y)) continue;
          const float g = gradient(x, y);
          const int bx = x / kBlock, by = y / kBlock;
          const float thr = thresholds.select(bx, by);
          if (g > thr && g > best) best = g, best_px = Eigen::Vector2f(x, y);
          if (g > std::max(0.5f * thr, thresholds.floor(bx, by)) && g > best_weak)
            best_weak = g, weak_px = Eigen::Vector2f(x, y);
        }
      }
      if (best > 0.f) {
        ++*cells;
        if (has_contrast(best_px)) out.push_back({best_px, best});
      } else if (best_weak > 0.f && ((cx / step + cy / step) % 2 == 0)) {
        ++*cells;  // Half the weak cells: coverage without crowding.
        if (has_contrast(weak_px)) out.push_back({weak_px, best_weak});
      }
    }
  }
  return out;
}

}  // namespace

float PatternContrast(const Image<float>& value, int x, int y) {
  PatternSamples v;
  for (int i = 0; i < kPatternSize; ++i) v[i] = value(x + kPattern[i][0], y + kPattern[i][1]);
  return std::sqrt(PatternVariance(v));
}

BlockThresholds ComputeBlockThresholds(const ImagePyramid& image, const CandidateSelectorOptions& options) {
  return BlockThresholdsOf(ReadLevel0(image), options);
}

std::vector<SelectedPixel> SelectCandidates(const ImagePyramid& image, const CandidateSelectorOptions& options,
                                            const Image<uint8_t>* valid_mask) {
  const Level0 level0 = ReadLevel0(image);
  const BlockThresholds thresholds = BlockThresholdsOf(level0, options);
  // Start from the step that would give the target on a fully textured image, then adapt.
  const double area = static_cast<double>(image.width(0)) * image.height(0);
  double step = std::max(2.0, std::sqrt(area / options.target_count));
  std::vector<SelectedPixel> best;
  double best_ratio = 0.0;
  for (int attempt = 0; attempt < 6; ++attempt) {
    int cells = 0;
    std::vector<SelectedPixel> sel = SelectWithStep(level0, thresholds, static_cast<int>(std::lround(step)),
                                                    options.border, valid_mask, &cells);
    // The step adapts to the cells with a pick, so dropped picks do not crowd the others.
    const double ratio = static_cast<double>(cells) / options.target_count;
    if (attempt == 0 || std::abs(ratio - 1.0) < std::abs(best_ratio - 1.0)) {
      best = std::move(sel);
      best_ratio = ratio;
    }
    if (ratio > 0.9 && ratio < 1.1) break;
    // Count scales roughly with 1 / step^2.
    step = std::max(2.0, step * std::sqrt(std::max(ratio, 0.05)));
  }
  return best;
}

}  // namespace dsm
