// SPDX-License-Identifier: MIT
// ImagePyramid::Sample8: the bilinear (I, dI/dx, dI/dy) of eight points at once, what one
// residual pattern needs. The scalar path is Sample per point; on CPUs with AVX2 the
// eight points run in the lanes of one register: the 6-byte pixels are fetched by 32-bit gathers
// (bytes 0-3, 4-7 and 8-11 from the left pixel: (I0, dx0), (dy0, I1), (dx1, dy1)), split by shifts
// and weighted in the same order, so both paths give the same floats bit for bit.
#include "dsm/image/pyramid.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(DSM_NO_SIMD_CLONES)
#include <immintrin.h>
#define DSM_SAMPLE8_AVX2 1
#endif

namespace dsm {
namespace {

#ifdef DSM_SAMPLE8_AVX2
// The low and the high signed 16 bits of each 32-bit lane, as floats.
__attribute__((target("avx2"))) inline __m256 LowSigned(__m256i a) {
  return _mm256_cvtepi32_ps(_mm256_srai_epi32(_mm256_slli_epi32(a, 16), 16));
}
__attribute__((target("avx2"))) inline __m256 HighSigned(__m256i a) {
  return _mm256_cvtepi32_ps(_mm256_srai_epi32(a, 16));
}
__attribute__((target("avx2"))) inline __m256 LowUnsigned(__m256i a) {
  return _mm256_cvtepi32_ps(_mm256_and_si256(a, _mm256_set1_epi32(0xffff)));
}
__attribute__((target("avx2"))) inline __m256 HighUnsigned(__m256i a) {
  return _mm256_cvtepi32_ps(_mm256_srli_epi32(a, 16));
}
// w00 a + w10 b + w01 c + w11 d, summed left to right as the scalar expression.
__attribute__((target("avx2"))) inline __m256 Blend(__m256 w00, __m256 w10, __m256 w01, __m256 w11, __m256 a, __m256 b,
                                                   __m256 c, __m256 d) {
  return _mm256_add_ps(
      _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(w00, a), _mm256_mul_ps(w10, b)), _mm256_mul_ps(w01, c)),
      _mm256_mul_ps(w11, d));
}

__attribute__((target("avx2"))) void Sample8Avx2(const Image<PixelFixed>& img, const float* x, const float* y,
                                                 float* value, float* dx, float* dy) {
  static_assert(sizeof(PixelFixed) == 6, "the gathers assume 6-byte pixels");
  const __m256 X = _mm256_loadu_ps(x), Y = _mm256_loadu_ps(y);
  const __m256i ix = _mm256_cvttps_epi32(X), iy = _mm256_cvttps_epi32(Y);
  const __m256 fx = _mm256_sub_ps(X, _mm256_cvtepi32_ps(ix)), fy = _mm256_sub_ps(Y, _mm256_cvtepi32_ps(iy));
  const __m256 one = _mm256_set1_ps(1.f);
  const __m256 gx_ = _mm256_sub_ps(one, fx), gy_ = _mm256_sub_ps(one, fy);
  const __m256 w00 = _mm256_mul_ps(gx_, gy_), w10 = _mm256_mul_ps(fx, gy_), w01 = _mm256_mul_ps(gx_, fy),
               w11 = _mm256_mul_ps(fx, fy);
  // Byte offsets of the left pixels: 6 (y w + x).
  const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(iy, _mm256_set1_epi32(img.width())), ix);
  const __m256i p_off = _mm256_add_epi32(_mm256_slli_epi32(index, 2), _mm256_slli_epi32(index, 1));
  const __m256i q_off = _mm256_add_epi32(p_off, _mm256_set1_epi32(6 * img.width()));
  const int* base = reinterpret_cast<const int*>(img.Row(0));
  const __m256i four = _mm256_set1_epi32(4), eight = _mm256_set1_epi32(8);
  const __m256i p0 = _mm256_i32gather_epi32(base, p_off, 1);
  const __m256i p1 = _mm256_i32gather_epi32(base, _mm256_add_epi32(p_off, four), 1);
  const __m256i p2 = _mm256_i32gather_epi32(base, _mm256_add_epi32(p_off, eight), 1);
  const __m256i q0 = _mm256_i32gather_epi32(base, q_off, 1);
  const __m256i q1 = _mm256_i32gather_epi32(base, _mm256_add_epi32(q_off, four), 1);
  const __m256i q2 = _mm256_i32gather_epi32(base, _mm256_add_epi32(q_off, eight), 1);
  const __m256 v = Blend(w00, w10, w01, w11, LowUnsigned(p0), HighUnsigned(p1), LowUnsigned(q0), HighUnsigned(q1));
  const __m256 gx = Blend(w00, w10, w01, w11, HighSigned(p0), LowSigned(p2), HighSigned(q0), LowSigned(q2));
  const __m256 gy = Blend(w00, w10, w01, w11, LowSigned(p1), HighSigned(p2), LowSigned(q1), HighSigned(q2));
  _mm256_storeu_ps(value, _mm256_mul_ps(v, _mm256_set1_ps(1.f / ImagePyramid::kValueScale)));
  _mm256_storeu_ps(dx, _mm256_mul_ps(gx, _mm256_set1_ps(1.f / ImagePyramid::kGradientScale)));
  _mm256_storeu_ps(dy, _mm256_mul_ps(gy, _mm256_set1_ps(1.f / ImagePyramid::kGradientScale)));
}

// Initialised before main, possibly before libgcc's own CPU probe: it runs it first.
const bool kHasAvx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
#endif

// The cubic B-spline's weights of the pixels -1, 0, 1, 2 for a point at fraction f past pixel 0,
//   B(f + 1) = (1 - f)^3 / 6,  B(f) = (3 f^3 - 6 f^2 + 4) / 6,
//   B(1 - f) = (-3 f^3 + 3 f^2 + 3 f + 1) / 6,  B(2 - f) = f^3 / 6,
// and their derivatives d/df.
inline void BSplineWeights(float f, float* w, float* d) {
  const float g = 1.f - f, f2 = f * f, f3 = f2 * f;
  w[0] = g * g * g * (1.f / 6.f);
  w[1] = (3.f * f3 - 6.f * f2 + 4.f) * (1.f / 6.f);
  w[2] = (-3.f * f3 + 3.f * f2 + 3.f * f + 1.f) * (1.f / 6.f);
  w[3] = f3 * (1.f / 6.f);
  d[0] = -0.5f * g * g;
  d[1] = 1.5f * f2 - 2.f * f;
  d[2] = -1.5f * f2 + f + 0.5f;
  d[3] = 0.5f * f2;
}

}  // namespace

PixelGrad ImagePyramid::SampleBSpline(int l, float x, float y) const {
  const Image<PixelFixed>& img = fixed_[l];
  const int ix = static_cast<int>(x), iy = static_cast<int>(y);
  float wx[4], dwx[4], wy[4], dwy[4];
  BSplineWeights(x - static_cast<float>(ix), wx, dwx);
  BSplineWeights(y - static_cast<float>(iy), wy, dwy);
  float v = 0.f, gx = 0.f, gy = 0.f;
  for (int j = 0; j < 4; ++j) {
    const PixelFixed* p = img.Row(iy - 1 + j) + ix - 1;
    const float p0 = p[0].value, p1 = p[1].value, p2 = p[2].value, p3 = p[3].value;
    const float row = wx[0] * p0 + wx[1] * p1 + wx[2] * p2 + wx[3] * p3;
    const float drow = dwx[0] * p0 + dwx[1] * p1 + dwx[2] * p2 + dwx[3] * p3;
    v += wy[j] * row;
    gx += wy[j] * drow;
    gy += dwy[j] * row;
  }
  constexpr float kScale = 1.f / kValueScale;
  return PixelGrad(v * kScale, gx * kScale, gy * kScale);
}

void ImagePyramid::Sample8(int l, const float* x, const float* y, float* value, float* dx, float* dy) const {
#ifdef DSM_SAMPLE8_AVX2
  if (kHasAvx2) return Sample8Avx2(fixed_[l], x, y, value, dx, dy);
#endif
  for (int k = 0; k < 8; ++k) {
    const PixelGrad g = Sample(l, x[k], y[k]);
    value[k] = g[0];
    dx[k] = g[1];
    dy[k] = g[2];
  }
}

}  // namespace dsm
