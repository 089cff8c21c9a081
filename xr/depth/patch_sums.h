// SPDX-License-Identifier: MIT
/// @brief The sphere sweep's inner work (#35): over a patch of n bilinear taps of the other image,
///        Σb, Σb² and Σa·b with the reference patch's mean-free values a — what one hypothesis's
///        zero-mean normalised cross-correlation needs. A scalar version, the reference, and an
///        AVX2 one (eight taps a step: two 32-bit gathers for the two pixel rows, the same integer
///        bilinear as the scalar one, so every b is equal; the sums differ in float rounding
///        order only), chosen at run time where the CPU has AVX2.
///
///        The AVX2 version reads each tap's two rows four bytes wide: up to two bytes past the
///        tap's 2 × 2 block. Inside an image that is the next pixels or the next row; only a tap in
///        the last block row within three pixels of its end could read past the image, and
///        `gatherSafe` says so (such patches take the scalar version). Its offsets are 32-bit:
///        images spanning over 2 GiB take the scalar version too (`gatherOffsetsFit`).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "xr/depth/bilinear_tap.h"

namespace telesphere::xr::depth {

/// Each sample b is summed as b − kPatchGreyOffset (exact: b is a multiple of 1/65536 below 256).
/// Σb² of a mid-grey patch is then about eight times smaller, and so is float's cancellation in
/// Σb² − (Σb)²/n, and Σa·b no longer carries 128 · Σa of the reference patch's float residue
/// (its mean is not exactly 0). Against a double reference at 2° tiles the worst cost was 5e-4
/// off, 0.09 where the other patch is nearly flat; with the shift 6e-5 and 5e-7
/// (tests/xr/test_gpu_sweep_costs.cpp). The variance and Σ(a − ā)·b are unchanged by it.
inline constexpr float kPatchGreyOffset = 128.0F;

/// Σ(b − 128), Σ(b − 128)², Σa·(b − 128) over a patch.
struct PatchSums {
  float b = 0, bb = 0, ab = 0;
};

/// The reference: one tap after another.
PatchSums patchSumsScalar(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, int n);

/// The AVX2 version where the CPU has it (and `simd`), else the scalar one.
PatchSums patchSums(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, int n, bool simd = true);

/// One hypothesis's cost from its sums: 1 − ZNCC of the mean-free reference patch (Σa² = `sum_aa`)
/// against the other's, over n taps; infinity where the other patch has no texture (Σ(b − b̄)² ≤
/// 1e-6).
inline float patchCost(const PatchSums& sums, float sum_aa, int n) {
  const float var_b = sums.bb - sums.b * sums.b * (1.0F / static_cast<float>(n));
  if (var_b <= 1e-6F) return std::numeric_limits<float>::infinity();
  return 1.0F - sums.ab / std::sqrt(sum_aa * var_b);  // Σ(a − ā)·b = Σ(a − ā)(b − b̄)
}

/// patchCost for `patches` patches of n taps each, stored one after another in `taps` (patch p's
/// at taps[p·n]), against the same reference patch: cost[p], infinity where usable[p] is 0. The
/// AVX2 version (where the CPU has it, `simd`, and every tap is gatherSafe) sums each patch as
/// patchSums does and takes eight costs a step, with the same operations as patchCost: every cost
/// is equal to patchCost(patchSums(…)) to the bit. A sweep's tile against all its hypotheses in
/// one call.
void patchCosts(const std::uint8_t* pixels, int stride, const BilinearTap* taps, const float* a, float sum_aa, int n,
                int patches, const std::uint8_t* usable, float* cost, bool simd = true);

/// Whether the AVX2 version may read tap `t` of an image `width` × `height` four bytes wide.
inline bool gatherSafe(const BilinearTap& t, int width, int height) {
  return !(t.y + 2 >= height && t.x + 3 >= width);
}

/// Whether the AVX2 version's pixel offsets (y·stride + x, 32-bit signed) reach every pixel of an
/// image of `height` rows `stride` bytes apart: images up to 2 GiB from first to last pixel. Where
/// not, callers pass `simd` false (the offsets would wrap and read elsewhere).
inline bool gatherOffsetsFit(int stride, int height) {
  return static_cast<std::int64_t>(stride) * height <= std::numeric_limits<std::int32_t>::max();
}

/// Whether this CPU runs the AVX2 version.
bool patchSumsSimdAvailable();

}  // namespace telesphere::xr::depth
