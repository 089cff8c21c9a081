// SPDX-License-Identifier: MIT
/// @brief findJpegBands and appendFillerBand: one header parser (ITU T.81 §B) for both.
#include "robot/link/media/jpeg_bands.h"

#include <algorithm>
#include <array>
#include <cstring>

namespace telesphere::link::media {
namespace {

struct Component {
  int id = 0, h = 1, v = 1;
  int dc_table = 0, ac_table = 0;
};

/// The canonical Huffman code of symbol 0x00 (DC: difference category 0; AC: end of block).
struct ZeroCode {
  std::uint16_t bits = 0;
  int length = 0;  ///< 0: the table has no code for it
};

struct Header {
  int width = 0, height = 0;
  std::vector<Component> frame;       ///< in SOF order
  std::vector<int> scan;              ///< indices into frame, in SOS order
  int restart_interval = 0;
  std::array<ZeroCode, 4> dc_zero{}, ac_eob{};
  std::array<bool, 4> dc_defined{}, ac_defined{};
  std::size_t header_bytes = 0;
  int hmax = 1, vmax = 1;
  int mcus_per_row = 0, mcu_rows = 0;
};

std::string hexMarker(std::uint8_t marker) {
  static const char* digits = "0123456789ABCDEF";
  return std::string("0xFF") + digits[marker >> 4] + digits[marker & 15];
}

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }

bool fail(std::string* error, const std::string& why) {
  *error = why;
  return false;
}

/// The code of symbol 0 from a DHT table's 16 counts and its symbols.
bool zeroCodeOf(const std::uint8_t* counts, const std::uint8_t* symbols, ZeroCode* out, std::string* error) {
  std::uint32_t code = 0;
  std::size_t k = 0;
  *out = {};
  for (int length = 1; length <= 16; ++length) {
    for (int i = 0; i < counts[length - 1]; ++i, ++k, ++code) {
      if (code >= (1u << length)) return fail(error, "a Huffman table with more codes than its lengths allow");
      if (symbols[k] == 0 && out->length == 0) *out = {static_cast<std::uint16_t>(code), length};
    }
    code <<= 1;
  }
  return true;
}

bool parseHeader(std::span<const std::uint8_t> d, Header* out, std::string* error) {
  Header h;
  if (d.size() < 4 || d[0] != 0xFF || d[1] != 0xD8) return fail(error, "not a JPEG (no SOI)");
  std::size_t pos = 2;
  bool have_frame = false;
  while (true) {
    if (pos + 4 > d.size()) return fail(error, "the JPEG ends before its SOS segment");
    if (d[pos] != 0xFF) return fail(error, "no marker at byte " + std::to_string(pos));
    while (pos + 4 <= d.size() && d[pos + 1] == 0xFF) ++pos;  // fill bytes
    if (pos + 4 > d.size()) return fail(error, "the JPEG ends before its SOS segment");
    const std::uint8_t marker = d[pos + 1];
    if (marker == 0xD9 || (marker >= 0xD0 && marker <= 0xD8) || marker == 0x01 || marker == 0x00)
      return fail(error, "marker " + hexMarker(marker) + " before the SOS segment");
    const std::size_t length = be16(&d[pos + 2]);
    if (length < 2 || pos + 2 + length > d.size())
      return fail(error, "a segment at byte " + std::to_string(pos) + " runs past the JPEG's end");
    const std::uint8_t* s = &d[pos + 4];
    const std::size_t n = length - 2;
    if (marker == 0xC0 || marker == 0xC1) {
      if (have_frame) return fail(error, "two SOF segments");
      if (n < 6 || s[0] != 8) return fail(error, "an SOF segment other than 8-bit");
      h.height = be16(s + 1);
      h.width = be16(s + 3);
      const int components = s[5];
      if (h.width == 0 || h.height == 0) return fail(error, "an image of zero size (DNL is not supported)");
      if (components < 1 || components > 4 || n != 6 + 3u * components) return fail(error, "a malformed SOF segment");
      for (int c = 0; c < components; ++c) {
        Component comp;
        comp.id = s[6 + 3 * c];
        comp.h = s[7 + 3 * c] >> 4;
        comp.v = s[7 + 3 * c] & 15;
        if (comp.h < 1 || comp.h > 4 || comp.v < 1 || comp.v > 4) return fail(error, "a sampling factor outside 1..4");
        h.hmax = std::max(h.hmax, comp.h);
        h.vmax = std::max(h.vmax, comp.v);
        h.frame.push_back(comp);
      }
      have_frame = true;
    } else if (marker >= 0xC2 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      return fail(error, "not a baseline Huffman JPEG (progressive, lossless or arithmetic-coded)");
    } else if (marker == 0xC4) {
      std::size_t k = 0;
      while (k < n) {
        if (k + 17 > n) return fail(error, "a truncated DHT segment");
        const int table_class = s[k] >> 4, id = s[k] & 15;
        if (table_class > 1 || id > 3) return fail(error, "a DHT table class or id out of range");
        std::size_t symbols = 0;
        for (int i = 0; i < 16; ++i) symbols += s[k + 1 + i];
        if (symbols > 256 || k + 17 + symbols > n) return fail(error, "a truncated DHT segment");
        ZeroCode zero;
        if (!zeroCodeOf(&s[k + 1], &s[k + 17], &zero, error)) return false;
        (table_class == 0 ? h.dc_zero : h.ac_eob)[id] = zero;
        (table_class == 0 ? h.dc_defined : h.ac_defined)[id] = true;
        k += 17 + symbols;
      }
    } else if (marker == 0xDD) {
      if (n != 2) return fail(error, "a malformed DRI segment");
      h.restart_interval = be16(s);
    } else if (marker == 0xDA) {
      if (!have_frame) return fail(error, "an SOS segment before the SOF segment");
      const int components = n >= 1 ? s[0] : 0;
      if (components < 1 || components > 4 || n != 4 + 2u * components)
        return fail(error, "a malformed SOS segment");
      if (components != static_cast<int>(h.frame.size()))
        return fail(error, "a JPEG in several scans (only one interleaved scan is supported)");
      for (int c = 0; c < components; ++c) {
        const int id = s[1 + 2 * c];
        const auto it = std::find_if(h.frame.begin(), h.frame.end(), [&](const Component& f) { return f.id == id; });
        if (it == h.frame.end()) return fail(error, "an SOS component the SOF does not have");
        it->dc_table = s[2 + 2 * c] >> 4;
        it->ac_table = s[2 + 2 * c] & 15;
        if (it->dc_table > 3 || it->ac_table > 3) return fail(error, "an SOS table id out of range");
        h.scan.push_back(static_cast<int>(it - h.frame.begin()));
      }
      const std::uint8_t* tail = s + 1 + 2 * components;
      if (tail[0] != 0 || tail[1] != 63 || tail[2] != 0) return fail(error, "not a sequential DCT scan");
      h.header_bytes = pos + 2 + length;
      break;
    }
    pos += 2 + length;
  }
  if (h.frame.size() == 1) {
    // One component: non-interleaved, an MCU is one block.
    h.mcus_per_row = (h.width + 7) / 8;
    h.mcu_rows = (h.height + 7) / 8;
    h.hmax = h.vmax = 1;
    h.frame[0].h = h.frame[0].v = 1;
  } else {
    h.mcus_per_row = (h.width + 8 * h.hmax - 1) / (8 * h.hmax);
    h.mcu_rows = (h.height + 8 * h.vmax - 1) / (8 * h.vmax);
  }
  *out = std::move(h);
  return true;
}

/// Bits into bytes, most significant first, a 0x00 after every 0xFF (T.81 §F.1.2.3).
class BitWriter {
 public:
  explicit BitWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  void put(std::uint32_t bits, int length) {
    for (int i = length - 1; i >= 0; --i) {
      byte_ = static_cast<std::uint8_t>(byte_ << 1 | ((bits >> i) & 1));
      if (++filled_ == 8) emit();
    }
  }
  /// Pads the last byte with 1-bits.
  void flush() {
    while (filled_ != 0) put(1, 1);
  }

 private:
  void emit() {
    out_.push_back(byte_);
    if (byte_ == 0xFF) out_.push_back(0x00);
    byte_ = 0;
    filled_ = 0;
  }
  std::vector<std::uint8_t>& out_;
  std::uint8_t byte_ = 0;
  int filled_ = 0;
};

}  // namespace

std::uint32_t JpegBands::bandOffset(std::size_t band) const {
  std::uint32_t offset = header_bytes;
  for (std::size_t i = 0; i < band && i < band_bytes.size(); ++i) offset += band_bytes[i];
  return offset;
}

std::pair<int, int> JpegBands::bandRows(std::size_t band) const {
  if (mcus_per_row <= 0 || band >= bandCount()) return {0, 0};
  const long long first_mcu = static_cast<long long>(band) * mcus_per_band;
  const long long end_mcu = std::min<long long>(mcus_total, first_mcu + mcus_per_band);
  const int first_row = static_cast<int>(first_mcu / mcus_per_row) * image_rows_per_mcu_row;
  const int end_row = static_cast<int>((end_mcu + mcus_per_row - 1) / mcus_per_row) * image_rows_per_mcu_row;
  return {std::min(first_row, height), std::min(end_row, height)};
}

std::optional<JpegBands> readJpegBandGeometry(std::span<const std::uint8_t> header, std::string* error) {
  Header h;
  if (!parseHeader(header, &h, error)) return std::nullopt;
  JpegBands bands;
  bands.width = h.width;
  bands.height = h.height;
  bands.header_bytes = static_cast<std::uint32_t>(h.header_bytes);
  bands.mcus_per_row = h.mcus_per_row;
  bands.mcus_total = h.mcus_per_row * h.mcu_rows;
  bands.mcus_per_band = h.restart_interval > 0 ? h.restart_interval : bands.mcus_total;
  bands.image_rows_per_mcu_row = 8 * h.vmax;
  return bands;
}

std::optional<JpegBands> findJpegBands(std::span<const std::uint8_t> jpeg, std::string* error) {
  std::optional<JpegBands> geometry = readJpegBandGeometry(jpeg, error);
  if (!geometry) return std::nullopt;
  JpegBands& bands = *geometry;
  const std::size_t expected = bands.bandCount();
  std::size_t band_start = bands.header_bytes;
  for (std::size_t i = bands.header_bytes; i + 1 < jpeg.size();) {
    if (jpeg[i] != 0xFF) {
      // Entropy-coded data is almost all bytes other than 0xFF: jump to the next one (a 4K frame
      // is scanned on the robot for every frame sent).
      const void* next_ff = std::memchr(jpeg.data() + i, 0xFF, jpeg.size() - i);
      if (!next_ff) break;
      i = static_cast<std::size_t>(static_cast<const std::uint8_t*>(next_ff) - jpeg.data());
      continue;
    }
    const std::uint8_t next = jpeg[i + 1];
    if (next == 0x00) {
      i += 2;
    } else if (next == 0xFF) {
      ++i;
    } else if (next >= 0xD0 && next <= 0xD7) {
      const std::size_t band = bands.band_bytes.size();
      if (next != 0xD0 + band % 8) {
        *error = "restart marker RST" + std::to_string(next - 0xD0) + " where RST" + std::to_string(band % 8) +
                 " belongs";
        return std::nullopt;
      }
      if (band + 1 >= expected) {
        *error = "more restart markers than the restart interval gives";
        return std::nullopt;
      }
      if (i == band_start) {
        *error = "an empty band before RST" + std::to_string(next - 0xD0);
        return std::nullopt;
      }
      bands.band_bytes.push_back(static_cast<std::uint32_t>(i + 2 - band_start));
      band_start = i + 2;
      i += 2;
    } else if (next == 0xD9) {
      if (i == band_start) {
        *error = "an empty band before EOI";
        return std::nullopt;
      }
      bands.band_bytes.push_back(static_cast<std::uint32_t>(i - band_start));
      bands.trailer_bytes = static_cast<std::uint32_t>(jpeg.size() - i);
      if (bands.bands() != expected) {
        *error = std::to_string(bands.bands()) + " bands where the restart interval gives " + std::to_string(expected);
        return std::nullopt;
      }
      return geometry;
    } else {
      *error = "marker " + hexMarker(next) + " inside the entropy-coded data";
      return std::nullopt;
    }
  }
  *error = "the JPEG has no EOI";
  return std::nullopt;
}

bool appendFillerBand(std::span<const std::uint8_t> header, const JpegBands& bands, std::size_t band,
                      std::vector<std::uint8_t>& out, std::string* error) {
  Header h;
  if (!parseHeader(header, &h, error)) return false;
  const int interval = h.restart_interval > 0 ? h.restart_interval : h.mcus_per_row * h.mcu_rows;
  if (h.mcus_per_row * h.mcu_rows != bands.mcus_total || interval != bands.mcus_per_band ||
      band >= bands.bandCount()) {
    *error = "the band layout does not belong to this header";
    return false;
  }
  for (const int c : h.scan) {
    const Component& comp = h.frame[static_cast<std::size_t>(c)];
    const auto dc = static_cast<std::size_t>(comp.dc_table), ac = static_cast<std::size_t>(comp.ac_table);
    if (!h.dc_defined[dc] || !h.ac_defined[ac] || h.dc_zero[dc].length == 0 || h.ac_eob[ac].length == 0) {
      *error = "the Huffman tables have no code for a zero block";
      return false;
    }
  }
  const long long first_mcu = static_cast<long long>(band) * bands.mcus_per_band;
  const long long mcus = std::min<long long>(bands.mcus_total - first_mcu, bands.mcus_per_band);
  BitWriter bits(out);
  for (long long m = 0; m < mcus; ++m)
    for (const int c : h.scan) {
      const Component& comp = h.frame[static_cast<std::size_t>(c)];
      const ZeroCode dc = h.dc_zero[static_cast<std::size_t>(comp.dc_table)];
      const ZeroCode ac = h.ac_eob[static_cast<std::size_t>(comp.ac_table)];
      for (int b = 0; b < comp.h * comp.v; ++b) {
        bits.put(dc.bits, dc.length);
        bits.put(ac.bits, ac.length);
      }
    }
  bits.flush();
  if (band + 1 < bands.bandCount()) {
    out.push_back(0xFF);
    out.push_back(static_cast<std::uint8_t>(0xD0 + band % 8));
  }
  return true;
}

}  // namespace telesphere::link::media
