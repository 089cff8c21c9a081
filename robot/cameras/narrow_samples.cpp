// SPDX-License-Identifier: MIT
/// @brief Wide sensor samples to 8 bits: one multiply and shift per sample in 32-bit integers (the
///        row loop vectorised, in an AVX2 and a default version like the debayer's), equal to the
///        rounded division for every 9–16-bit value.
#include "robot/cameras/narrow_samples.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "robot/cameras/row_kernel.h"

namespace telesphere::robot::cameras {
namespace {

/// round(255 · 2^24 / max): with it, (v · k + 2^23) >> 24 equals round(v · 255 / max) for every
/// v ≤ max and every width 9–16 (checked for all values by the tests), and max · k + 2^23 < 2^32.
std::uint32_t scaleFor(std::uint32_t max) {
  return static_cast<std::uint32_t>((255ull * (1ull << 24) + max / 2) / max);
}

/// One row: `n` words (little-endian, any alignment) to bytes.
TELESPHERE_ROW_KERNEL
void narrowRow(const std::uint8_t* __restrict in, std::uint8_t* __restrict out, int n, std::uint32_t max, std::uint32_t k) {
  for (int x = 0; x < n; ++x) {
    std::uint16_t word = 0;
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(&word, in + 2 * x, 2);  // an unaligned load the vectoriser widens
    } else {
      word = static_cast<std::uint16_t>(in[2 * x] | (in[2 * x + 1] << 8));
    }
    const std::uint32_t v = std::min<std::uint32_t>(word, max);
    out[x] = static_cast<std::uint8_t>((v * k + (1u << 23)) >> 24);
  }
}

bool fail(std::string* error, const std::string& reason) {
  if (error) *error = "narrowSamplesTo8Bits: " + reason;
  return false;
}

}  // namespace

std::uint8_t narrowSampleTo8Bits(std::uint16_t v, int sample_bits) {
  const std::uint32_t max = (1u << sample_bits) - 1;
  if (v >= max) return 255;
  return static_cast<std::uint8_t>((2u * 255u * v + max) / (2u * max));
}

bool narrowSamplesTo8Bits(const std::uint8_t* src, int width, int height, int src_stride_bytes, int sample_bits,
                          std::uint8_t* dst, int dst_stride_bytes, std::string* error) {
  if (sample_bits < kMinWideSampleBits || sample_bits > kMaxWideSampleBits)
    return fail(error, std::to_string(sample_bits) + " bits per sample (9 to 16 are narrowed; 8 needs no narrowing)");
  if (!src || !dst) return fail(error, "no pixels");
  if (width < 1 || height < 1) return fail(error, "empty image " + std::to_string(width) + "x" + std::to_string(height));
  if (src_stride_bytes < 2 * width)
    return fail(error, "source rows " + std::to_string(src_stride_bytes) + " bytes apart, less than 2 x width " +
                           std::to_string(2 * width));
  if (dst_stride_bytes < width)
    return fail(error, "destination rows " + std::to_string(dst_stride_bytes) + " bytes apart, less than width " +
                           std::to_string(width));
  const std::uint32_t max = (1u << sample_bits) - 1;
  const std::uint32_t k = scaleFor(max);
  for (int y = 0; y < height; ++y)
    narrowRow(src + static_cast<std::ptrdiff_t>(y) * src_stride_bytes, dst + static_cast<std::ptrdiff_t>(y) * dst_stride_bytes,
              width, max, k);
  return true;
}

}  // namespace telesphere::robot::cameras
