// SPDX-License-Identifier: MIT
// Undistorter::Remap8: the bilinear remap of an 8-bit image (Bilinear, image.h), eight output
// pixels a vector on CPUs with AVX2. Each lane fetches its two neighbours of a row with one
// 32-bit gather (bytes ix, ix + 1 of rows iy and iy + 1) and weights them in Bilinear's order,
//   (1 - fy) ((1 - fx) I00 + fx I10) + fy ((1 - fx) I01 + fx I11),
// with separate multiplies and adds, so both paths give the same floats bit for bit.
#include "dsm/geometry/undistorter.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(DSM_NO_SIMD_CLONES)
#include <immintrin.h>
#define DSM_REMAP_AVX2 1
#endif

namespace dsm {
namespace {

#ifdef DSM_REMAP_AVX2
__attribute__((target("avx2"))) void RemapRun8(const uint8_t* input, int input_width, const int32_t* offset,
                                               const float* frac_x, const float* frac_y, float* out) {
  const __m256i top = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(offset));
  const __m256i bottom = _mm256_add_epi32(top, _mm256_set1_epi32(input_width));
  const int* base = reinterpret_cast<const int*>(input);
  const __m256i p = _mm256_i32gather_epi32(base, top, 1), q = _mm256_i32gather_epi32(base, bottom, 1);
  const __m256i byte = _mm256_set1_epi32(0xff);
  const __m256 i00 = _mm256_cvtepi32_ps(_mm256_and_si256(p, byte));
  const __m256 i10 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(p, 8), byte));
  const __m256 i01 = _mm256_cvtepi32_ps(_mm256_and_si256(q, byte));
  const __m256 i11 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(q, 8), byte));
  const __m256 fx = _mm256_loadu_ps(frac_x), fy = _mm256_loadu_ps(frac_y), one = _mm256_set1_ps(1.f);
  const __m256 gx = _mm256_sub_ps(one, fx), gy = _mm256_sub_ps(one, fy);
  const __m256 row0 = _mm256_add_ps(_mm256_mul_ps(gx, i00), _mm256_mul_ps(fx, i10));
  const __m256 row1 = _mm256_add_ps(_mm256_mul_ps(gx, i01), _mm256_mul_ps(fx, i11));
  _mm256_storeu_ps(out, _mm256_add_ps(_mm256_mul_ps(gy, row0), _mm256_mul_ps(fy, row1)));
}

const bool kHasAvx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
#endif

}  // namespace

bool Undistorter::Remap8(const Image<uint8_t>& distorted, Image<float>* out) const {
#ifdef DSM_REMAP_AVX2
  if (!kHasAvx2) return false;
  DSM_CHECK(distorted.width() == input_.width && distorted.height() == input_.height,
            "image size differs from the calibration");
  const int w = output_.width, runs = w / 8;
  *out = Image<float>(w, output_.height, 0.f);
  for (int v = 0; v < output_.height; ++v) {
    float* row = out->Row(v);
    const uint8_t* ok = valid_.Row(v);
    const size_t base = static_cast<size_t>(v) * w;
    // Pixels [u0, u1) of the row one by one, as Remap does.
    const auto scalar = [&](int u0, int u1) {
      for (int u = u0; u < u1; ++u)
        if (ok[u]) row[u] = Bilinear(distorted, map_x_[base + u], map_y_[base + u]);
    };
    for (int r = 0; r < runs; ++r) {
      const int u = 8 * r;
      if (run_ok_[static_cast<size_t>(v) * runs + r]) {
        RemapRun8(distorted.data(), input_.width, &offset_[base + u], &frac_x_[base + u], &frac_y_[base + u], row + u);
      } else {
        scalar(u, u + 8);
      }
    }
    scalar(8 * runs, w);  // The row's tail.
  }
  return true;
#else
  return false;
#endif
}

}  // namespace dsm
