// SPDX-License-Identifier: MIT
#include "dsm/tracking/rolling_shutter.h"

#include <algorithm>
#include <cmath>

#include "dsm/lie/so3.h"
#include "dsm/util/simd.h"

#if DSM_X86_SIMD
#include <immintrin.h>
#endif

namespace dsm {

namespace {

constexpr int kSegment = 32;  // Pixels of a row between two exactly mapped ones.

// out[i] = the image at (x0 + i sx, y0 + i sy), bilinear, for i < n; the coordinates clamped to
// [0, max_x] x [0, max_y] (max_x < width - 1, max_y < height - 1: the 2x2 neighbourhood is inside).
void SampleAlong(const float* image, int stride, float x0, float sx, float y0, float sy, float max_x, float max_y,
                 int begin, int n, float* out) {
  for (int i = begin; i < n; ++i) {
    const float x = std::clamp(x0 + static_cast<float>(i) * sx, 0.f, max_x);
    const float y = std::clamp(y0 + static_cast<float>(i) * sy, 0.f, max_y);
    const int xi = static_cast<int>(x), yi = static_cast<int>(y);
    const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
    const float* p = image + yi * stride + xi;
    const float top = p[0] + fx * (p[1] - p[0]);
    const float bottom = p[stride] + fx * (p[stride + 1] - p[stride]);
    out[i] = top + fy * (bottom - top);
  }
}

#if DSM_X86_SIMD
// The same, 8 pixels at a time with AVX2 gathers (the same operations in the same order: the
// same values); the rest as above.
__attribute__((target("avx2"))) void SampleAlongAvx2(const float* image, int stride, float x0, float sx, float y0,
                                                      float sy, float max_x, float max_y, int n, float* out) {
  const __m256 lane = _mm256_setr_ps(0.f, 1.f, 2.f, 3.f, 4.f, 5.f, 6.f, 7.f);
  const __m256 zero = _mm256_setzero_ps(), mx = _mm256_set1_ps(max_x), my = _mm256_set1_ps(max_y);
  const __m256i vstride = _mm256_set1_epi32(stride), one = _mm256_set1_epi32(1);
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 index = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(i)), lane);
    const __m256 x = _mm256_min_ps(_mm256_max_ps(_mm256_add_ps(_mm256_set1_ps(x0), _mm256_mul_ps(index, _mm256_set1_ps(sx))), zero), mx);
    const __m256 y = _mm256_min_ps(_mm256_max_ps(_mm256_add_ps(_mm256_set1_ps(y0), _mm256_mul_ps(index, _mm256_set1_ps(sy))), zero), my);
    const __m256i xi = _mm256_cvttps_epi32(x), yi = _mm256_cvttps_epi32(y);
    const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(xi)), fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(yi));
    const __m256i at = _mm256_add_epi32(_mm256_mullo_epi32(yi, vstride), xi);
    const __m256i below = _mm256_add_epi32(at, vstride);
    const __m256 p00 = _mm256_i32gather_ps(image, at, 4), p01 = _mm256_i32gather_ps(image, _mm256_add_epi32(at, one), 4);
    const __m256 p10 = _mm256_i32gather_ps(image, below, 4);
    const __m256 p11 = _mm256_i32gather_ps(image, _mm256_add_epi32(below, one), 4);
    const __m256 top = _mm256_add_ps(p00, _mm256_mul_ps(fx, _mm256_sub_ps(p01, p00)));
    const __m256 bottom = _mm256_add_ps(p10, _mm256_mul_ps(fx, _mm256_sub_ps(p11, p10)));
    _mm256_storeu_ps(out + i, _mm256_add_ps(top, _mm256_mul_ps(fy, _mm256_sub_ps(bottom, top))));
  }
  SampleAlong(image, stride, x0, sx, y0, sy, max_x, max_y, i, n, out);
}

bool HasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

void Sample(const float* image, int stride, float x0, float sx, float y0, float sy, float max_x, float max_y, int n,
            float* out) {
#if DSM_X86_SIMD
  if (HasAvx2()) return SampleAlongAvx2(image, stride, x0, sx, y0, sy, max_x, max_y, n, out);
#endif
  SampleAlong(image, stride, x0, sx, y0, sy, max_x, max_y, 0, n, out);
}

}  // namespace

Image<float> RectifyRotation(const Image<float>& image, const PinholeCamera& camera, const ReadoutTurn& turn) {
  const double line_delay_s = turn.line_delay_s;
  const Eigen::Vector3d& angular_velocity = turn.angular_velocity;
  const int w = image.width(), h = image.height();
  Image<float> out(w, h);
  const Eigen::Matrix3d K = camera.K(), K_inv = K.inverse();
  // Just inside the last pixel, so that the 2x2 neighbourhood never leaves the image.
  const float max_x = static_cast<float>(w - 1) - 1e-3f, max_y = static_cast<float>(h - 1) - 1e-3f;
  const int stride = static_cast<int>(image.Row(1) - image.Row(0));
  for (int v = 0; v < h; ++v) {
    // The row's turn: tau from the source row of the row's centre pixel.
    Eigen::Matrix3d H = Eigen::Matrix3d::Identity();
    double tau = v * line_delay_s;
    for (int step = 0; step < 2; ++step) {
      H = K * SO3d::Exp(angular_velocity * tau).Matrix() * K_inv;
      const Eigen::Vector3d q = H * Eigen::Vector3d(0.5 * (w - 1), v, 1.0);
      tau = std::clamp(q.y() / q.z(), 0.0, static_cast<double>(h - 1)) * line_delay_s;
    }
    H = K * SO3d::Exp(angular_velocity * tau).Matrix() * K_inv;
    const auto source = [&](int u) {
      const Eigen::Vector3d q = H * Eigen::Vector3d(u, v, 1.0);
      return Eigen::Vector2d(q.x() / q.z(), q.y() / q.z());
    };
    // The homography exactly every kSegment pixels, linear in between (its curvature over a
    // segment is far below a hundredth of a pixel at these turns).
    Eigen::Vector2d a = source(0);
    for (int u0 = 0; u0 < w; u0 += kSegment) {
      const int n = std::min(kSegment, w - u0);
      const Eigen::Vector2d b = source(u0 + kSegment);
      const Eigen::Vector2d slope = (b - a) / kSegment;
      Sample(image.Row(0), stride, static_cast<float>(a.x()), static_cast<float>(slope.x()),
                  static_cast<float>(a.y()), static_cast<float>(slope.y()), max_x, max_y, n, out.Row(v) + u0);
      a = b;
    }
  }
  return out;
}

}  // namespace dsm
