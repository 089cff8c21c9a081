// SPDX-License-Identifier: MIT
/// @brief Bilinear demosaicing of 8-bit Bayer mosaics straight into YUV 4:2:0 planes.
#include "robot/cameras/debayer_yuv420.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include "robot/cameras/debayer.h"
#include "robot/cameras/row_kernel.h"

namespace telesphere::robot::cameras {
namespace {

// JPEG's RGB → YCbCr (JFIF) with libjpeg's 16-bit coefficients (jccolor.c), Y from one pixel at 4×
// the sample scale (shift 16 + 2), Cb and Cr from the sum of a 2×2 block at 4× (shift 16 + 4).
constexpr std::uint32_t kYr = 19595, kYg = 38470, kYb = 7471;        // 0.299, 0.587, 0.114
constexpr std::int32_t kCbR = -11059, kCbG = -21709, kCbB = 32768;    // −0.16874, −0.33126, 0.5
constexpr std::int32_t kCrR = 32768, kCrG = -27439, kCrB = -5329;     // 0.5, −0.41869, −0.08131
// Chroma rounds half down, as libjpeg does, so 255.5 (pure blue's Cb) stays 255.
constexpr std::int32_t kChromaOffset = (128 << 20) + (1 << 19) - 1;

inline std::uint8_t luma(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
  return static_cast<std::uint8_t>((kYr * r + kYg * g + kYb * b + (1u << 17)) >> 18);
}

/// Row y with the border mirrored without repeating the edge (row −1 reads row 1, row h row h − 2).
inline int mirrorRow(int y, int height) {
  if (y < 0) y = -y;
  if (y >= height) y = 2 * (height - 1) - y;
  return std::clamp(y, 0, height - 1);
}

/// The even and odd columns of `pairs` column pairs of a row, apart.
TELESPHERE_ROW_KERNEL
void splitColumns(const std::uint8_t* __restrict row, std::uint16_t* __restrict even, std::uint16_t* __restrict odd,
                  int pairs) {
  for (int i = 0; i < pairs; ++i) {
    even[i] = row[2 * i];
    odd[i] = row[2 * i + 1];
  }
}

/// The demosaiced values of pixel pair i of a row (column 2i, column 2i + 1) at 4× scale: the
/// row's own colour (R in a red row, B in a blue row), G, and the opposite colour.
struct PairRgb4 {
  std::uint16_t own_even, green_even, other_even, own_odd, green_odd, other_odd;
};

/// Own colour in the even columns, G in the odd ones: a colour site takes G from its 4 edge
/// neighbours and the opposite colour from its 4 diagonals; a G site the row's colour from left
/// and right, the other from up and down.
inline PairRgb4 colourEvenAt(const std::uint16_t* u_even, const std::uint16_t* u_odd, const std::uint16_t* m_even,
                             const std::uint16_t* m_odd, const std::uint16_t* d_even, const std::uint16_t* d_odd, int i) {
  return {static_cast<std::uint16_t>(4 * m_even[i]),
          static_cast<std::uint16_t>(m_odd[i - 1] + m_odd[i] + u_even[i] + d_even[i]),
          static_cast<std::uint16_t>(u_odd[i - 1] + u_odd[i] + d_odd[i - 1] + d_odd[i]),
          static_cast<std::uint16_t>(2 * (m_even[i] + m_even[i + 1])),
          static_cast<std::uint16_t>(4 * m_odd[i]),
          static_cast<std::uint16_t>(2 * (u_odd[i] + d_odd[i]))};
}

/// G in the even columns, own colour in the odd ones (the same rules).
inline PairRgb4 colourOddAt(const std::uint16_t* u_even, const std::uint16_t* u_odd, const std::uint16_t* m_even,
                            const std::uint16_t* m_odd, const std::uint16_t* d_even, const std::uint16_t* d_odd, int i) {
  return {static_cast<std::uint16_t>(2 * (m_odd[i - 1] + m_odd[i])),
          static_cast<std::uint16_t>(4 * m_even[i]),
          static_cast<std::uint16_t>(2 * (u_even[i] + d_even[i])),
          static_cast<std::uint16_t>(4 * m_odd[i]),
          static_cast<std::uint16_t>(m_even[i] + m_even[i + 1] + u_odd[i] + d_odd[i]),
          static_cast<std::uint16_t>(u_even[i] + u_even[i + 1] + d_even[i] + d_even[i + 1])};
}

/// Pixel pair i of a row whose own colour sits in the even columns (else in the odd ones).
template <bool kColourInEven>
inline PairRgb4 pairAt(const std::uint16_t* u_even, const std::uint16_t* u_odd, const std::uint16_t* m_even,
                       const std::uint16_t* m_odd, const std::uint16_t* d_even, const std::uint16_t* d_odd, int i) {
  if constexpr (kColourInEven) return colourEvenAt(u_even, u_odd, m_even, m_odd, d_even, d_odd, i);
  else return colourOddAt(u_even, u_odd, m_even, m_odd, d_even, d_odd, i);
}

/// A row's values, even and odd columns apart (Y and the block sums follow in passes of their
/// own: a pass that also wrote Y and the sums mixed 8-, 16- and 32-bit lanes and ran slower, 5.5
/// against 4.4 ms per 4K image).
template <bool kColourInEven>
[[gnu::always_inline]] inline void demosaicRowLoop(const std::uint16_t* __restrict u_even, const std::uint16_t* __restrict u_odd,
                            const std::uint16_t* __restrict m_even, const std::uint16_t* __restrict m_odd,
                            const std::uint16_t* __restrict d_even, const std::uint16_t* __restrict d_odd,
                            std::uint16_t* __restrict own_even, std::uint16_t* __restrict own_odd,
                            std::uint16_t* __restrict green_even, std::uint16_t* __restrict green_odd,
                            std::uint16_t* __restrict other_even, std::uint16_t* __restrict other_odd, int n) {
  for (int i = 0; i < n; ++i) {
    const PairRgb4 p = pairAt<kColourInEven>(u_even, u_odd, m_even, m_odd, d_even, d_odd, i);
    own_even[i] = p.own_even;
    green_even[i] = p.green_even;
    other_even[i] = p.other_even;
    own_odd[i] = p.own_odd;
    green_odd[i] = p.green_odd;
    other_odd[i] = p.other_odd;
  }
}

// The clone: a template cannot carry target_clones, so this picks the loop, which is inlined into
// each version (always_inline: else each version calls the default one).
TELESPHERE_ROW_KERNEL
void demosaicRowKernel(bool colour_in_even, const std::uint16_t* __restrict u_even, const std::uint16_t* __restrict u_odd,
                       const std::uint16_t* __restrict m_even, const std::uint16_t* __restrict m_odd,
                       const std::uint16_t* __restrict d_even, const std::uint16_t* __restrict d_odd,
                       std::uint16_t* __restrict own_even, std::uint16_t* __restrict own_odd,
                       std::uint16_t* __restrict green_even, std::uint16_t* __restrict green_odd,
                       std::uint16_t* __restrict other_even, std::uint16_t* __restrict other_odd, int n) {
  if (colour_in_even)
    demosaicRowLoop<true>(u_even, u_odd, m_even, m_odd, d_even, d_odd, own_even, own_odd, green_even, green_odd,
                          other_even, other_odd, n);
  else
    demosaicRowLoop<false>(u_even, u_odd, m_even, m_odd, d_even, d_odd, own_even, own_odd, green_even, green_odd,
                           other_even, other_odd, n);
}

/// Y of `pairs` pixel pairs, written interleaved (even column, odd column).
TELESPHERE_ROW_KERNEL
void lumaRow(const std::uint16_t* __restrict r_even, const std::uint16_t* __restrict r_odd,
             const std::uint16_t* __restrict g_even, const std::uint16_t* __restrict g_odd,
             const std::uint16_t* __restrict b_even, const std::uint16_t* __restrict b_odd,
             std::uint8_t* __restrict y, int pairs) {
  for (int i = 0; i < pairs; ++i) {
    y[2 * i] = luma(r_even[i], g_even[i], b_even[i]);
    y[2 * i + 1] = luma(r_odd[i], g_odd[i], b_odd[i]);
  }
}

/// Sums of one colour over the 2 × 2 blocks of rows a and b (≤ 4 080: 16 bits hold them, and
/// the products below are 16 × 16 → 32 bits, which vectorise without a 32-bit multiply).
TELESPHERE_ROW_KERNEL
void blockSums(const std::uint16_t* __restrict a_even, const std::uint16_t* __restrict a_odd,
               const std::uint16_t* __restrict b_even, const std::uint16_t* __restrict b_odd,
               std::int16_t* __restrict sums, int n) {
  for (int i = 0; i < n; ++i) sums[i] = static_cast<std::int16_t>(a_even[i] + a_odd[i] + b_even[i] + b_odd[i]);
}

/// Cb and Cr from the block sums of R, G and B.
TELESPHERE_ROW_KERNEL
void chromaRow(const std::int16_t* __restrict sr, const std::int16_t* __restrict sg,
               const std::int16_t* __restrict sb, std::uint8_t* __restrict cb, std::uint8_t* __restrict cr, int n) {
  for (int i = 0; i < n; ++i) {
    const std::int32_t r = sr[i], g = sg[i], b = sb[i];
    cb[i] = static_cast<std::uint8_t>((kCbR * r + kCbG * g + kCbB * b + kChromaOffset) >> 20);
    cr[i] = static_cast<std::uint8_t>((kCrR * r + kCrG * g + kCrB * b + kChromaOffset) >> 20);
  }
}

}  // namespace

void DebayerToYuv420::split(const std::uint8_t* row, int width, SplitRow& out) const {
  const int n_even = (width + 1) / 2, n_odd = width / 2;
  std::uint16_t* even = out.even.data() + 1;
  std::uint16_t* odd = out.odd.data() + 1;
  splitColumns(row, even, odd, n_odd);
  if (n_even > n_odd) even[n_even - 1] = row[width - 1];
  // The guards: column −1 reads column 1, column w reads column w − 2 (as debayerBilinear).
  odd[-1] = odd[0];
  even[n_even] = even[n_even - 1];  // w even: column w; w odd: read only for the dropped pixel w
  if (n_even > n_odd) odd[n_odd] = odd[n_odd - 1];
}

void DebayerToYuv420::demosaicRow(const SplitRow& up, const SplitRow& mid, const SplitRow& down, int width,
                                  bool red_row, int colour_parity, Rgb4Row& out) const {
  const int n = (width + 1) / 2;
  const std::uint16_t* u_even = up.even.data() + 1;
  const std::uint16_t* u_odd = up.odd.data() + 1;
  const std::uint16_t* m_even = mid.even.data() + 1;
  const std::uint16_t* m_odd = mid.odd.data() + 1;
  const std::uint16_t* d_even = down.even.data() + 1;
  const std::uint16_t* d_odd = down.odd.data() + 1;
  // This row's own colour (R in a red row, B in a blue row) and the opposite one.
  std::uint16_t* own_even = red_row ? out.r_even.data() : out.b_even.data();
  std::uint16_t* own_odd = red_row ? out.r_odd.data() : out.b_odd.data();
  std::uint16_t* other_even = red_row ? out.b_even.data() : out.r_even.data();
  std::uint16_t* other_odd = red_row ? out.b_odd.data() : out.r_odd.data();
  std::uint16_t* green_even = out.g_even.data();
  std::uint16_t* green_odd = out.g_odd.data();
  demosaicRowKernel(colour_parity == 0, u_even, u_odd, m_even, m_odd, d_even, d_odd, own_even, own_odd, green_even,
                    green_odd, other_even, other_odd, n);
  if (width % 2 == 1) {  // no pixel right of the last one: it counts twice in its chroma mean
    own_odd[n - 1] = own_even[n - 1];
    green_odd[n - 1] = green_even[n - 1];
    other_odd[n - 1] = other_even[n - 1];
  }
}

bool DebayerToYuv420::convert(const std::uint8_t* src, int width, int height, int src_stride, PixelFormat layout,
                              Yuv420Image& out, std::string* error) {
  if (!checkMosaic("DebayerToYuv420", src, width, height, src_stride, layout, error)) return false;

  const int red_x = redSiteOf(layout).x, red_y = redSiteOf(layout).y;
  out.resize(width, height);
  const int n = (width + 1) / 2;  // pixel pairs per row = chroma samples per row
  const std::size_t split_size = static_cast<std::size_t>(n) + 2;
  for (SplitRow& row : split_) {
    row.even.resize(split_size);
    row.odd.resize(split_size);
  }
  for (auto& sums : sums_) sums.resize(static_cast<std::size_t>(n));
  for (Rgb4Row& row : rows_)
    for (auto* plane : {&row.r_even, &row.r_odd, &row.g_even, &row.g_odd, &row.b_even, &row.b_odd})
      plane->resize(static_cast<std::size_t>(n));
  const auto splitRow = [&](int y, SplitRow& into) {
    split(src + static_cast<std::ptrdiff_t>(mirrorRow(y, height)) * src_stride, width, into);
  };
  const auto demosaic = [&](int y, const SplitRow& up, const SplitRow& mid, const SplitRow& down, Rgb4Row& into) {
    const bool red_row = (y & 1) == red_y;
    demosaicRow(up, mid, down, width, red_row, red_row ? red_x : 1 - red_x, into);
  };

  const int chroma_width = out.chromaWidth();
  const int pairs = width / 2;  // whole pixel pairs in a row (an odd last pixel apart)
  for (int cy = 0; cy < out.chromaHeight(); ++cy) {
    const int y0 = 2 * cy;
    const bool two_rows = y0 + 1 < height;  // else the last row counts twice (edge replicated)
    // split_[0..3]: rows y0 − 1 … y0 + 2; the last two are the next chroma row's first two.
    if (cy == 0) {
      splitRow(y0 - 1, split_[0]);
      splitRow(y0, split_[1]);
    } else {
      std::swap(split_[0], split_[2]);
      std::swap(split_[1], split_[3]);
    }
    splitRow(y0 + 1, split_[2]);
    if (two_rows) splitRow(y0 + 2, split_[3]);
    std::uint8_t* const cb = out.u.data() + static_cast<std::size_t>(cy) * chroma_width;
    std::uint8_t* const cr = out.v.data() + static_cast<std::size_t>(cy) * chroma_width;
    demosaic(y0, split_[0], split_[1], split_[2], rows_[0]);
    if (two_rows) demosaic(y0 + 1, split_[1], split_[2], split_[3], rows_[1]);
    const Rgb4Row& a = rows_[0];
    const Rgb4Row& b = two_rows ? rows_[1] : rows_[0];
    for (int k = 0; k < (two_rows ? 2 : 1); ++k) {
      const Rgb4Row& row = rows_[k];
      std::uint8_t* y_row = out.y.data() + static_cast<std::size_t>(y0 + k) * width;
      lumaRow(row.r_even.data(), row.r_odd.data(), row.g_even.data(), row.g_odd.data(), row.b_even.data(),
              row.b_odd.data(), y_row, pairs);
      if (width % 2 == 1) y_row[width - 1] = luma(row.r_even[n - 1], row.g_even[n - 1], row.b_even[n - 1]);
    }
    blockSums(a.r_even.data(), a.r_odd.data(), b.r_even.data(), b.r_odd.data(), sums_[0].data(), chroma_width);
    blockSums(a.g_even.data(), a.g_odd.data(), b.g_even.data(), b.g_odd.data(), sums_[1].data(), chroma_width);
    blockSums(a.b_even.data(), a.b_odd.data(), b.b_even.data(), b.b_odd.data(), sums_[2].data(), chroma_width);
    chromaRow(sums_[0].data(), sums_[1].data(), sums_[2].data(), cb, cr, chroma_width);
  }
  return true;
}

}  // namespace telesphere::robot::cameras
