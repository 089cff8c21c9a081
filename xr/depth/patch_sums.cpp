// SPDX-License-Identifier: MIT
/// @brief patchSums: the scalar reference and the AVX2 version with its run-time choice.
#include "xr/depth/patch_sums.h"

#include <algorithm>
#include <limits>

#include "xr/depth/patch_sums_avx2.h"

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

using avx2::LaneSums;
using avx2::rounded;

/// The eight-lane sums of a patch's whole steps of eight tabled taps.
__attribute__((target("avx2,fma"), always_inline)) inline LaneSums laneSumsAvx2(const std::uint8_t* pixels, int stride,
                                                                               const BilinearTap* taps, const float* a, int whole) {
  static_assert(sizeof(BilinearTap) == 8, "a tap is one 64-bit lane: x, y, wx, wy");
  const __m256i low_dwords = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  const __m256i mask16 = _mm256_set1_epi32(0xFFFF);
  const __m256i stride_v = _mm256_set1_epi32(stride);
  LaneSums sums = avx2::zeroLanes();
  for (int i = 0; i < whole; i += 8) {
    // Eight taps: (x | y << 16) and (wx | wy << 16) of each, in tap order.
    const __m256i t0 = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(taps + i)), low_dwords);
    const __m256i t1 = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(taps + i + 4)), low_dwords);
    const __m256i xy = _mm256_permute2x128_si256(t0, t1, 0x20), w = _mm256_permute2x128_si256(t0, t1, 0x31);
    const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(xy, 16), stride_v), _mm256_and_si256(xy, mask16));
    avx2::addStep(pixels, stride, offset, _mm256_and_si256(w, mask16), _mm256_srli_epi32(w, 16), a + i, sums);
  }
  return sums;
}

__attribute__((target("avx2,fma"))) PatchSums patchSumsAvx2(const std::uint8_t* pixels, int stride,
                                                            const BilinearTap* taps, const float* a, int n) {
  const int whole = n - n % 8;
  const PatchSums lanes = avx2::totals(laneSumsAvx2(pixels, stride, taps, a, whole));
  // The rest goes through the scalar sums, compiled without AVX (legacy SSE encodings). GCC 12
  // put no vzeroupper anywhere in this function (objdump): neither before that call nor before
  // returning after it, so the scalar sums and then the sweep's own SSE code ran with the ymm
  // registers' upper halves dirty, each instruction paying a transition. On a Xeon with AVX-512
  // that made the whole sweep 5.5x slower (41.8 against 7.65 ms a pair, telesphere-bench depth),
  // slower than the one-at-a-time sums. Cleared here, before the call, both run clean.
  _mm256_zeroupper();
  const PatchSums rest = patchSumsScalar(pixels, stride, taps + whole, a + whole, n - whole);
  return avx2::plus(lanes, rest);
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
      // The last n mod 8 taps as patchSumsScalar adds them: summed on their own, then added.
      const PatchSums sums = avx2::plus(avx2::totals(laneSumsAvx2(pixels, stride, t, a, whole)),
                                        avx2::scalarSums(pixels, stride, t + whole, a + whole, n - whole));
      b[j] = sums.b;
      bb[j] = sums.bb;
      ab[j] = sums.ab;
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
