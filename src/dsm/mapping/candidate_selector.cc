// SPDX-License-Identifier: MIT
#include "dsm/mapping/candidate_selector.h"

#include <algorithm>
#include <cmath>

#include "dsm/util/check.h"

namespace dsm {

void CandidateSelectorOptions::Validate() const {
  if (target_count < 10 || target_count > 100000) throw InputError("candidates.target_count must be within 10..100000");
  if (!(threshold_margin >= 0)) throw InputError("candidates.threshold_margin must be non-negative");
  if (border < 2) throw InputError("candidates.border must be at least 2");
}

namespace {

constexpr int kBlock = 32;

// Per-block thresholds: median gradient + margin, smoothed with the 3 x 3 neighbouring blocks.
Image<float> BlockThresholds(const Image<PixelGrad>& level0, float margin) {
  const int bw = (level0.width() + kBlock - 1) / kBlock, bh = (level0.height() + kBlock - 1) / kBlock;
  Image<float> raw(bw, bh), smooth(bw, bh);
  std::vector<float> g;
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      g.clear();
      for (int y = by * kBlock; y < std::min(level0.height(), (by + 1) * kBlock); ++y)
        for (int x = bx * kBlock; x < std::min(level0.width(), (bx + 1) * kBlock); ++x) {
          const PixelGrad& p = level0(x, y);
          g.push_back(std::sqrt(p[1] * p[1] + p[2] * p[2]));
        }
      std::nth_element(g.begin(), g.begin() + g.size() / 2, g.end());
      raw(bx, by) = g[g.size() / 2] + margin;
    }
  }
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      float sum = 0.f;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = bx + dx, y = by + dy;
          if (x < 0 || y < 0 || x >= bw || y >= bh) continue;
          sum += raw(x, y);
          ++n;
        }
      smooth(bx, by) = sum / n;
    }
  return smooth;
}

std::vector<SelectedPixel> SelectWithStep(const ImagePyramid& image, const Image<float>& thresholds, int step,
                                          int border, const Image<uint8_t>* mask) {
  std::vector<SelectedPixel> out;
  const Image<PixelGrad>& l0 = image.level(0);
  const int w = l0.width(), h = l0.height();
  for (int cy = border; cy < h - border; cy += step) {
    for (int cx = border; cx < w - border; cx += step) {
      // Level 0: the strongest pixel above its block threshold; else a weaker one (coarser detail).
      float best = 0.f, best_weak = 0.f;
      Eigen::Vector2f best_px, weak_px;
      for (int y = cy; y < std::min(cy + step, h - border); ++y) {
        for (int x = cx; x < std::min(cx + step, w - border); ++x) {
          if (mask && !(*mask)(x, y)) continue;
          const PixelGrad& p = l0(x, y);
          const float g = std::sqrt(p[1] * p[1] + p[2] * p[2]);
          const float thr = thresholds(x / kBlock, y / kBlock);
          if (g > thr && g > best) best = g, best_px = Eigen::Vector2f(x, y);
          if (g > 0.5f * thr && g > best_weak) best_weak = g, weak_px = Eigen::Vector2f(x, y);
        }
      }
      if (best > 0.f) {
        out.push_back({best_px, best});
      } else if (best_weak > 0.f && ((cx / step + cy / step) % 2 == 0)) {
        out.push_back({weak_px, best_weak});  // Half the weak cells: coverage without crowding.
      }
    }
  }
  return out;
}

}  // namespace

std::vector<SelectedPixel> SelectCandidates(const ImagePyramid& image, const CandidateSelectorOptions& options,
                                            const Image<uint8_t>* valid_mask) {
  const Image<float> thresholds = BlockThresholds(image.level(0), options.threshold_margin);
  // Start from the step that would give the target on a fully textured image, then adapt.
  const double area = static_cast<double>(image.width(0)) * image.height(0);
  double step = std::max(2.0, std::sqrt(area / options.target_count));
  std::vector<SelectedPixel> best;
  for (int attempt = 0; attempt < 6; ++attempt) {
    std::vector<SelectedPixel> sel = SelectWithStep(image, thresholds, static_cast<int>(std::lround(step)),
                                                    options.border, valid_mask);
    const double ratio = static_cast<double>(sel.size()) / options.target_count;
    if (best.empty() || std::abs(ratio - 1.0) < std::abs(static_cast<double>(best.size()) / options.target_count - 1.0))
      best = std::move(sel);
    if (ratio > 0.9 && ratio < 1.1) break;
    // Count scales roughly with 1 / step^2.
    step = std::max(2.0, step * std::sqrt(std::max(ratio, 0.05)));
  }
  return best;
}

}  // namespace dsm
