// SPDX-License-Identifier: MIT
/// @brief The AVX2 steps of the patch sums (patch_sums.h), shared by the sums over tabled taps
///        (patch_sums.cpp) and over taps made from a patch's corners (patch_projection.cpp), so that
///        both add the same products in the same order. Only for .cpp files that check
///        TELESPHERE_PATCH_SUMS_AVX2; every function here runs only where the CPU has AVX2 and FMA
///        (patchSumsSimdAvailable).
#pragma once

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define TELESPHERE_PATCH_SUMS_AVX2 1

#include "xr/depth/patch_sums.h"

namespace telesphere::xr::depth::avx2 {

__attribute__((target("avx2,fma"), always_inline)) inline float horizontalSum(__m256 v) {
  const __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  const __m128 t = _mm_add_ps(s, _mm_movehl_ps(s, s));
  return _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
}

/// A row's two pixels (the low two bytes of each lane) weighted across: p0·(256 − wx) + p1·wx.
__attribute__((target("avx2,fma"), always_inline)) inline __m256i across(__m256i row, __m256i wx, __m256i full) {
  const __m256i mask8 = _mm256_set1_epi32(0xFF);
  const __m256i left = _mm256_and_si256(row, mask8), right = _mm256_and_si256(_mm256_srli_epi32(row, 8), mask8);
  return _mm256_add_epi32(_mm256_mullo_epi32(left, _mm256_sub_epi32(full, wx)), _mm256_mullo_epi32(right, wx));
}

/// A product GCC may not fuse into the sum or difference it feeds (it fuses even intrinsics' vector
/// products here, where FMA is on): the scalar code, without FMA, rounds both.
template <typename V>
__attribute__((target("avx2,fma"), always_inline)) inline V rounded(V product) {
  __asm__("" : "+x"(product));
  return product;
}

/// x·y + z rounded twice, as the scalar sums compute it.
__attribute__((target("avx2,fma"), always_inline)) inline float productPlus(float x, float y, float z) { return z + rounded(x * y); }

/// Σ(b − 128), Σ(b − 128)², Σa·(b − 128) over `count` taps one at a time, each product rounded before
/// it is added, as patchSumsScalar (compiled without FMA) adds them: for the taps past a patch's last
/// whole step of eight, inside AVX code.
__attribute__((target("avx2,fma"), always_inline)) inline PatchSums scalarSums(const std::uint8_t* pixels, int stride,
                                                                              const BilinearTap* taps, const float* a, int count) {
  PatchSums s;
  for (int i = 0; i < count; ++i) {
    const float v = tapGrey(pixels, stride, taps[i]) - kPatchGreyOffset;
    s.b += v;
    s.bb = productPlus(v, v, s.bb);
    s.ab = productPlus(a[i], v, s.ab);
  }
  return s;
}

/// The eight-lane sums of a patch's whole steps of eight taps, left in their lanes.
struct LaneSums {
  __m256 b, bb, ab;
};

/// Lanes at zero (a LaneSums has no constructor: it would be compiled without AVX).
__attribute__((target("avx2,fma"), always_inline)) inline LaneSums zeroLanes() {
  return {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
}

/// One step of eight taps into the lanes: each tap's top-left pixel at byte `offset` (y·stride + x),
/// its weights wx and wy (0–256); `a` the reference patch's eight values. The scalar tap's integer
/// bilinear (every b equal to tapGrey's), less kPatchGreyOffset.
__attribute__((target("avx2,fma"), always_inline)) inline void addStep(const std::uint8_t* pixels, int stride, __m256i offset, __m256i wx,
                                                                        __m256i wy, const float* a, LaneSums& sums) {
  const __m256i full = _mm256_set1_epi32(256);
  const __m256 scale = _mm256_set1_ps(1.0F / 65536.0F);
  const __m256i grey_offset = _mm256_set1_epi32(static_cast<int>(kPatchGreyOffset) * 65536);
  const __m256i row0 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(pixels), offset, 1);
  const __m256i row1 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(pixels + stride), offset, 1);
  // As the scalar tap: top = p00·(256 − wx) + p01·wx, bottom likewise, v = top·(256 − wy) + bottom·wy.
  const __m256i top = across(row0, wx, full), bottom = across(row1, wx, full);
  const __m256i v = _mm256_add_epi32(_mm256_mullo_epi32(top, _mm256_sub_epi32(full, wy)), _mm256_mullo_epi32(bottom, wy));
  const __m256 b = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(v, grey_offset)), scale);  // b − 128, as the scalar sums
  sums.b = _mm256_add_ps(sums.b, b);
  sums.bb = _mm256_fmadd_ps(b, b, sums.bb);
  sums.ab = _mm256_fmadd_ps(_mm256_loadu_ps(a), b, sums.ab);
}

/// The lanes' totals (horizontal sums), taken before a vzeroupper clears the lanes' upper halves.
__attribute__((target("avx2,fma"), always_inline)) inline PatchSums totals(const LaneSums& lanes) {
  return {horizontalSum(lanes.b), horizontalSum(lanes.bb), horizontalSum(lanes.ab)};
}

/// The whole steps' totals plus the sums of the taps past them (added on their own first, as
/// patchSumsScalar adds them): what the AVX2 patchSums returns.
inline PatchSums plus(PatchSums whole, const PatchSums& rest) {
  whole.b += rest.b;
  whole.bb += rest.bb;
  whole.ab += rest.ab;
  return whole;
}

}  // namespace telesphere::xr::depth::avx2
#endif
