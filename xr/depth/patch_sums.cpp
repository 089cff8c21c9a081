// SPDX-License-Identifier: MIT
/// @brief patchSums: the scalar reference and the AVX2 version with its run-time choice.
#include "xr/depth/patch_sums.h"

#include <algorithm>
#include <limits>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define TELESPHERE_PATCH_SUMS_AVX2 1
#endif

namespace telesphere::xr::depth {

PatchSums patchSumsScalar(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, int n) {
  PatchSums s;
  for (int i = 0; i < n; ++i) {
    const float b = tapGrey(pixels, stride, taps[i]) - kPatchGreyOffset;
    s.b += b;
    s.bb += b * b;
    s.ab += a[i] * b;  // Σ(a − ā)·b = Σ(a − ā)(b − b̄)
  }
  return s;
}

#ifdef TELESPHERE_PATCH_SUMS_AVX2
namespace {

__attribute__((target("avx2,fma"))) float horizontalSum(__m256 v) {
  const __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  const __m128 t = _mm_add_ps(s, _mm_movehl_ps(s, s));
  return _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
}

/// A row's two pixels (the low two bytes of each lane) weighted across: p0·(256 − wx) + p1·wx.
__attribute__((target("avx2,fma"))) inline __m256i across(__m256i row, __m256i wx, __m256i full) {
  const __m256i mask8 = _mm256_set1_epi32(0xFF);
  const __m256i left = _mm256_and_si256(row, mask8), right = _mm256_and_si256(_mm256_srli_epi32(row, 8), mask8);
  return _mm256_add_epi32(_mm256_mullo_epi32(left, _mm256_sub_epi32(full, wx)), _mm256_mullo_epi32(right, wx));
}

/// A product GCC may not fuse into the sum or difference it feeds (it fuses even intrinsics' vector
/// products here, where FMA is on): the scalar code, without FMA, rounds both.
template <typename V>
__attribute__((target("avx2,fma"))) inline V rounded(V product) {
  __asm__("" : "+x"(product));
  return product;
}

/// x·y + z rounded twice, as the scalar sums compute it.
__attribute__((target("avx2,fma"))) inline float productPlus(float x, float y, float z) { return z + rounded(x * y); }

/// The eight-lane sums of a patch's whole steps of eight taps, left in their lanes.
struct LaneSums {
  __m256 b, bb, ab;
};

__attribute__((target("avx2,fma"), always_inline)) inline LaneSums laneSumsAvx2(const std::uint8_t* pixels, int stride,
                                                                               const BilinearTap* taps, const float* a, int whole) {
  static_assert(sizeof(BilinearTap) == 8, "a tap is one 64-bit lane: x, y, wx, wy");
  const __m256i low_dwords = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  const __m256i mask16 = _mm256_set1_epi32(0xFFFF);
  const __m256i stride_v = _mm256_set1_epi32(stride), full = _mm256_set1_epi32(256);
  const __m256 scale = _mm256_set1_ps(1.0F / 65536.0F);
  const __m256i grey_offset = _mm256_set1_epi32(static_cast<int>(kPatchGreyOffset) * 65536);
  __m256 sum_b = _mm256_setzero_ps(), sum_bb = _mm256_setzero_ps(), sum_ab = _mm256_setzero_ps();
  for (int i = 0; i < whole; i += 8) {
    // Eight taps: (x | y << 16) and (wx | wy << 16) of each, in tap order.
    const __m256i t0 = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(taps + i)), low_dwords);
    const __m256i t1 = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(taps + i + 4)), low_dwords);
    const __m256i xy = _mm256_permute2x128_si256(t0, t1, 0x20), w = _mm256_permute2x128_si256(t0, t1, 0x31);
    const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(xy, 16), stride_v), _mm256_and_si256(xy, mask16));
    const __m256i row0 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(pixels), offset, 1);
    const __m256i row1 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(pixels + stride), offset, 1);
    const __m256i wx = _mm256_and_si256(w, mask16), wy = _mm256_srli_epi32(w, 16);
    // As the scalar tap: top = p00·(256 − wx) + p01·wx, bottom likewise, v = top·(256 − wy) + bottom·wy.
    const __m256i top = across(row0, wx, full), bottom = across(row1, wx, full);
    const __m256i v = _mm256_add_epi32(_mm256_mullo_epi32(top, _mm256_sub_epi32(full, wy)), _mm256_mullo_epi32(bottom, wy));
    const __m256 b = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(v, grey_offset)), scale);  // b − 128, as the scalar sums
    sum_b = _mm256_add_ps(sum_b, b);
    sum_bb = _mm256_fmadd_ps(b, b, sum_bb);
    sum_ab = _mm256_fmadd_ps(_mm256_loadu_ps(a + i), b, sum_ab);
  }
  return {sum_b, sum_bb, sum_ab};
}

__attribute__((target("avx2,fma"))) PatchSums patchSumsAvx2(const std::uint8_t* pixels, int stride,
                                                            const BilinearTap* taps, const float* a, int n) {
  const int whole = n - n % 8;
  const LaneSums lanes = laneSumsAvx2(pixels, stride, taps, a, whole);
  PatchSums s{horizontalSum(lanes.b), horizontalSum(lanes.bb), horizontalSum(lanes.ab)};
  // The rest goes through the scalar sums, compiled without AVX (legacy SSE encodings). GCC 12
  // put no vzeroupper anywhere in this function (objdump): neither before that call nor before
  // returning after it, so the scalar sums and then the sweep's own SSE code ran with the ymm
  // registers' upper halves dirty, each instruction paying a transition. On a Xeon with AVX-512
  // that made the whole sweep 5.5x slower (41.8 against 7.65 ms a pair, telesphere-bench depth),
  // slower than the one-at-a-time sums. Cleared here, before the call, both run clean.
  _mm256_zeroupper();
  const PatchSums rest = patchSumsScalar(pixels, stride, taps + whole, a + whole, n - whole);
  s.b += rest.b;
  s.bb += rest.bb;
  s.ab += rest.ab;
  return s;
}

__attribute__((target("avx2,fma"))) void patchCostsAvx2(const std::uint8_t* pixels, int stride, const BilinearTap* taps,
                                                        const float* a, float sum_aa, int n, int patches,
                                                        const std::uint8_t* usable, float* cost) {
  const int whole = n - n % 8;
  const __m256 inv_n = _mm256_set1_ps(1.0F / static_cast<float>(n)), aa = _mm256_set1_ps(sum_aa);
  const __m256 one = _mm256_set1_ps(1.0F), min_var = _mm256_set1_ps(1e-6F);
  const __m256 infinity = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  for (int first = 0; first < patches; first += 8) {
    // Eight patches' sums (a lane each), then their costs in one step.
    alignas(32) float b[8] = {}, bb[8] = {}, ab[8] = {}, use[8] = {};
    const int count = std::min(8, patches - first);
    for (int j = 0; j < count; ++j) {
      const int p = first + j;
      if (!usable[p]) continue;
      const BilinearTap* t = taps + static_cast<std::size_t>(p) * n;
      const LaneSums lanes = laneSumsAvx2(pixels, stride, t, a, whole);
      b[j] = horizontalSum(lanes.b);
      bb[j] = horizontalSum(lanes.bb);
      ab[j] = horizontalSum(lanes.ab);
      // The last n mod 8 taps as patchSumsScalar adds them: summed on their own, then added.
      float rest_b = 0, rest_bb = 0, rest_ab = 0;
      for (int i = whole; i < n; ++i) {
        const float v = tapGrey(pixels, stride, t[i]) - kPatchGreyOffset;
        rest_b += v;
        rest_bb = productPlus(v, v, rest_bb);
        rest_ab = productPlus(a[i], v, rest_ab);
      }
      b[j] += rest_b;
      bb[j] += rest_bb;
      ab[j] += rest_ab;
      use[j] = 1.0F;
    }
    // As patchCost: var_b = Σb² − (Σb·Σb)·(1/n); cost = 1 − Σab / √(Σa²·var_b).
    const __m256 vb = _mm256_load_ps(b), vbb = _mm256_load_ps(bb), vab = _mm256_load_ps(ab);
    const __m256 var_b = _mm256_sub_ps(vbb, rounded(_mm256_mul_ps(_mm256_mul_ps(vb, vb), inv_n)));
    const __m256 c = _mm256_sub_ps(one, _mm256_div_ps(vab, _mm256_sqrt_ps(_mm256_mul_ps(aa, var_b))));
    const __m256 valid = _mm256_and_ps(_mm256_cmp_ps(var_b, min_var, _CMP_GT_OQ), _mm256_cmp_ps(_mm256_load_ps(use), one, _CMP_EQ_OQ));
    alignas(32) float out[8];
    _mm256_store_ps(out, _mm256_blendv_ps(infinity, c, valid));
    for (int j = 0; j < count; ++j) cost[first + j] = out[j];
  }
  _mm256_zeroupper();  // as in patchSumsAvx2: the caller's SSE code runs clean
}

}  // namespace
#endif

bool patchSumsSimdAvailable() {
#ifdef TELESPHERE_PATCH_SUMS_AVX2
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
#else
  return false;
#endif
}

void patchCosts(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, float sum_aa, int n,
                int patches, const std::uint8_t* usable, float* cost, bool simd) {
#ifdef TELESPHERE_PATCH_SUMS_AVX2
  if (simd && patchSumsSimdAvailable()) {
    patchCostsAvx2(pixels, stride, taps, a, sum_aa, n, patches, usable, cost);
    return;
  }
#endif
  for (int p = 0; p < patches; ++p)
    cost[p] = usable[p] ? patchCost(patchSumsScalar(pixels, stride, taps + static_cast<std::size_t>(p) * n, a, n), sum_aa, n)
                        : std::numeric_limits<float>::infinity();
}

PatchSums patchSums(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, int n, bool simd) {
#ifdef TELESPHERE_PATCH_SUMS_AVX2
  if (simd && patchSumsSimdAvailable()) return patchSumsAvx2(pixels, stride, taps, a, n);
#endif
  return patchSumsScalar(pixels, stride, taps, a, n);
}

}  // namespace telesphere::xr::depth
