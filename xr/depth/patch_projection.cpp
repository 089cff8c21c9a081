// SPDX-License-Identifier: MIT
/// @brief projectPatch: every sample, or the four corners and bilinear between them; the taps
///        between corners, one at a time or four at a step (AVX2).
#include "xr/depth/patch_projection.h"

#include <algorithm>
#include <cassert>
#include <vector>

#include "xr/depth/patch_sums.h"

#include "xr/depth/patch_sums_avx2.h"

namespace telesphere::xr::depth {
namespace {

/// The point at depth 1/ρ along d, in the view's frame (up to its positive scale 1/ρ), projected.
bool projectAt(const calib::GenericCamera& camera, const Eigen::Vector3f& d, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
               double rho, Eigen::Vector2d& px) {
  return camera.project(R * d.cast<double>() + rho * t, px);
}

#ifdef TELESPHERE_PATCH_SUMS_AVX2
using avx2::rounded;  // betweenCorners, compiled without FMA, rounds each product

/// Each lane's 32-bit integer from four 64-bit compare masks (all ones or zero).
__attribute__((target("avx2,fma"), always_inline)) inline __m128i maskToInt32(__m256d mask) {
  const __m256i low_dwords = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(mask), low_dwords));
}

/// bilinearTap's corner pixel and weight along one axis, four lanes: x0 = clamp(trunc(p), 0,
/// size − 2); the weight clamp(trunc(f·256) + (f·256 − trunc(f·256) ≥ ½), 0, 256) with f = p − x0.
__attribute__((target("avx2,fma"), always_inline)) inline void tapAxis(__m256d p, int size, __m128i& corner, __m128i& weight) {
  const __m128i zero = _mm_setzero_si128();
  corner = _mm_min_epi32(_mm_max_epi32(_mm256_cvttpd_epi32(p), zero), _mm_set1_epi32(size - 2));
  const __m256d scaled = _mm256_mul_pd(_mm256_sub_pd(p, _mm256_cvtepi32_pd(corner)), _mm256_set1_pd(256.0));
  const __m128i whole = _mm256_cvttpd_epi32(scaled);
  const __m128i half_up = maskToInt32(_mm256_cmp_pd(_mm256_sub_pd(scaled, _mm256_cvtepi32_pd(whole)), _mm256_set1_pd(0.5), _CMP_GE_OQ));
  weight = _mm_min_epi32(_mm_max_epi32(_mm_sub_epi32(whole, half_up), zero), _mm_set1_epi32(256));
}

/// (1 − u)·((1 − v)·q00 + v·q01) + u·((1 − v)·q10 + v·q11), each product rounded as betweenCorners's.
__attribute__((target("avx2,fma"), always_inline)) inline __m256d blend(__m256d u, __m256d v, __m256d not_u, __m256d not_v, __m256d q00,
                                                                         __m256d q01, __m256d q10, __m256d q11) {
  const __m256d top = _mm256_add_pd(rounded(_mm256_mul_pd(not_v, q00)), rounded(_mm256_mul_pd(v, q01)));
  const __m256d bottom = _mm256_add_pd(rounded(_mm256_mul_pd(not_v, q10)), rounded(_mm256_mul_pd(v, q11)));
  return _mm256_add_pd(rounded(_mm256_mul_pd(not_u, top)), rounded(_mm256_mul_pd(u, bottom)));
}

/// Each sample's u = i/(n − 1) and v = j/(n − 1) of an n × n patch, as betweenCorners divides,
/// padded with zeros to whole steps of four; kept for the last n.
struct SampleFractions {
  const double* u;
  const double* v;
};

SampleFractions sampleFractions(int n) {
  thread_local std::vector<double> u_table, v_table;
  thread_local int table_n = 0;
  if (table_n != n) {
    const int count = n * n;
    u_table.assign(static_cast<std::size_t>(count + 3) / 4 * 4, 0.0);
    v_table.assign(u_table.size(), 0.0);
    for (int s = 0; s < count; ++s) {
      u_table[s] = static_cast<double>(s / n) / (n - 1);
      v_table[s] = static_cast<double>(s % n) / (n - 1);
    }
    table_n = n;
  }
  return {u_table.data(), v_table.data()};
}

/// Four taps' corner pixels and weights, 32 bits a lane.
struct FourTaps {
  __m128i x, y, wx, wy;
};

/// The corners, each coordinate in every lane.
struct CornerLanes {
  __m256d x00, x01, x10, x11, y00, y01, y10, y11;
};

__attribute__((target("avx2,fma"), always_inline)) inline CornerLanes cornerLanes(const PatchCorners& c) {
  return {_mm256_set1_pd(c.p00.x()), _mm256_set1_pd(c.p01.x()), _mm256_set1_pd(c.p10.x()), _mm256_set1_pd(c.p11.x()),
          _mm256_set1_pd(c.p00.y()), _mm256_set1_pd(c.p01.y()), _mm256_set1_pd(c.p10.y()), _mm256_set1_pd(c.p11.y())};
}

/// The taps of samples s … s + 3: bilinearTap(betweenCorners(…)) of each, to the bit.
__attribute__((target("avx2,fma"), always_inline)) inline FourTaps fourTaps(const CornerLanes& c, SampleFractions f, int s, int width,
                                                                             int height) {
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d u = _mm256_loadu_pd(f.u + s), v = _mm256_loadu_pd(f.v + s);
  const __m256d not_u = _mm256_sub_pd(one, u), not_v = _mm256_sub_pd(one, v);
  FourTaps t;
  tapAxis(blend(u, v, not_u, not_v, c.x00, c.x01, c.x10, c.x11), width, t.x, t.wx);
  tapAxis(blend(u, v, not_u, not_v, c.y00, c.y01, c.y10, c.y11), height, t.y, t.wy);
  return t;
}

/// Four taps as BilinearTaps: the first `count` (1–4) of them written to `out`. (An n × n patch
/// leaves 0 or 1 past its last whole step of four.)
__attribute__((target("avx2,fma"), always_inline)) inline void storeTaps(const FourTaps& t, int count, BilinearTap* out) {
  static_assert(sizeof(BilinearTap) == 8, "a tap is x, y, wx, wy: 16 bits each");
  // (x, y, wx, wy), 16 bits each (all below 65536).
  const __m128i xy = _mm_or_si128(t.x, _mm_slli_epi32(t.y, 16)), w = _mm_or_si128(t.wx, _mm_slli_epi32(t.wy, 16));
  // One 32-byte store, as the sums load these four taps (a load is forwarded from one store, not
  // from two; no difference measured here).
  const __m256i taps = _mm256_set_m128i(_mm_unpackhi_epi32(xy, w), _mm_unpacklo_epi32(xy, w));
  if (count >= 4) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), taps);
    return;
  }
  alignas(32) BilinearTap four[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(four), taps);
  for (int k = 0; k < count; ++k) out[k] = four[k];
}

__attribute__((target("avx2,fma"))) void tapsBetweenCornersAvx2(const PatchCorners& corners, int n, int width, int height,
                                                                 BilinearTap* out) {
  const SampleFractions fractions = sampleFractions(n);
  const CornerLanes c = cornerLanes(corners);
  const int count = n * n;
  for (int s = 0; s < count; s += 4) storeTaps(fourTaps(c, fractions, s, width, height), std::min(4, count - s), out + s);
  _mm256_zeroupper();  // the caller's SSE code runs clean (patch_sums.cpp says what it cost without)
}

/// patchSumsBetweenCorners where every tap may be gathered four bytes wide: eight taps a step made
/// in registers and summed as the tabled taps' AVX2 sums sum them (patch_sums_avx2.h), the taps past
/// the last whole step written out and summed as patchSumsScalar sums them.
__attribute__((target("avx2,fma"))) PatchSums patchSumsBetweenCornersAvx2(const std::uint8_t* pixels, int stride, int width, int height,
                                                                         const PatchCorners& corners, int n, const float* a) {
  const SampleFractions fractions = sampleFractions(n);
  const CornerLanes c = cornerLanes(corners);
  const int count = n * n, whole = count - count % 8;
  const __m256i stride_v = _mm256_set1_epi32(stride);
  avx2::LaneSums lanes = avx2::zeroLanes();
  for (int s = 0; s < whole; s += 8) {
    const FourTaps low = fourTaps(c, fractions, s, width, height), high = fourTaps(c, fractions, s + 4, width, height);
    const __m256i x = _mm256_set_m128i(high.x, low.x), y = _mm256_set_m128i(high.y, low.y);
    const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(y, stride_v), x);
    avx2::addStep(pixels, stride, offset, _mm256_set_m128i(high.wx, low.wx), _mm256_set_m128i(high.wy, low.wy), a + s, lanes);
  }
  BilinearTap rest[8];
  for (int s = whole; s < count; s += 4) storeTaps(fourTaps(c, fractions, s, width, height), std::min(4, count - s), rest + (s - whole));
  const PatchSums sums = avx2::plus(avx2::totals(lanes), avx2::scalarSums(pixels, stride, rest, a + whole, count - whole));
  _mm256_zeroupper();
  return sums;
}
#endif

}  // namespace

bool projectPatchCorners(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                         const Eigen::Isometry3d& T_view_reference, double rho, PatchCorners& out) {
  assert(n >= 1 && directions);
  const Eigen::Matrix3d R = T_view_reference.linear();
  const Eigen::Vector3d t = T_view_reference.translation();
  // The model chosen once, its projection inlined: the four corners' square roots and divisions
  // overlap instead of waiting on each other through a call each.
  return camera.visit([&](const auto& model) {
    const auto at = [&](int s, Eigen::Vector2d& px) { return model.project(R * directions[s].template cast<double>() + rho * t, px); };
    const bool p00 = at(0, out.p00), p01 = at(n - 1, out.p01), p10 = at((n - 1) * n, out.p10), p11 = at(n * n - 1, out.p11);
    return p00 && p01 && p10 && p11;
  });
}

bool projectPatch(const calib::GenericCamera& camera, const Eigen::Vector3f* directions, int n,
                  const Eigen::Isometry3d& T_view_reference, double rho, bool corners_only, Eigen::Vector2d* px_out) {
  assert(n >= 1 && directions && px_out);
  if (!corners_only || n < 3) {
    const Eigen::Matrix3d R = T_view_reference.linear();
    const Eigen::Vector3d t = T_view_reference.translation();
    for (int s = 0; s < n * n; ++s)
      if (!projectAt(camera, directions[s], R, t, rho, px_out[s])) return false;
    return true;
  }
  PatchCorners corners;
  if (!projectPatchCorners(camera, directions, n, T_view_reference, rho, corners)) return false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) px_out[i * n + j] = betweenCorners(corners, n, i, j);
  return true;
}

void tapsBetweenCorners(const PatchCorners& corners, int n, int width, int height, BilinearTap* out, bool simd) {
  assert(n >= 2 && out);
#ifdef TELESPHERE_PATCH_SUMS_AVX2
  if (simd && patchSumsSimdAvailable()) {
    tapsBetweenCornersAvx2(corners, n, width, height, out);
    return;
  }
#endif
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out[i * n + j] = bilinearTap(betweenCorners(corners, n, i, j), width, height);
}

PatchSums patchSumsBetweenCorners(const std::uint8_t* pixels, int stride, int width, int height, const PatchCorners& corners, int n,
                                  const float* a, bool simd) {
  assert(n >= 2 && pixels && a);
  const int count = n * n;
#ifdef TELESPHERE_PATCH_SUMS_AVX2
  if (simd && patchSumsSimdAvailable()) {
    // Every sample lies within the corners' box, up to the interpolation's rounding (~1e-11 px):
    // a box half a pixel clear of the last block row, or of the last three columns, keeps every tap
    // gather-safe (gatherSafe), and the taps need not be written out to be checked.
    const double max_x = std::max({corners.p00.x(), corners.p01.x(), corners.p10.x(), corners.p11.x()});
    const double max_y = std::max({corners.p00.y(), corners.p01.y(), corners.p10.y(), corners.p11.y()});
    if (max_y < height - 2.5 || max_x < width - 3.5) return patchSumsBetweenCornersAvx2(pixels, stride, width, height, corners, n, a);
  }
#endif
  thread_local std::vector<BilinearTap> taps;
  taps.resize(count);
  tapsBetweenCorners(corners, n, width, height, taps.data(), simd);
  const bool gather_safe = std::all_of(taps.begin(), taps.end(), [&](const BilinearTap& t) { return gatherSafe(t, width, height); });
  return patchSums(pixels, stride, taps.data(), a, count, simd && gather_safe);
}

}  // namespace telesphere::xr::depth
