// SPDX-License-Identifier: MIT
/// @brief A baseline JPEG as the media path sees it (DESIGN.md §9): a header (through the SOS
///        segment), then bands of entropy-coded data separated by restart markers, then EOI.
///        Each band decodes on its own (DC prediction restarts), so the sender tells the receiver
///        where the bands lie, and the receiver, missing a band, writes a filler band in its
///        place: all blocks zero (mid grey), in the header's own Huffman codes, ending in the
///        right RSTn, so the JPEG stays valid and only that band is lost. Which image rows a band
///        covers is known, so the operator side can paint them from the previous frame.
///
///        Every length and count is checked against the bytes at hand: this parses what arrives
///        from the network.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace telesphere::link::media {

/// Where a JPEG's bands lie and what a band holds.
struct JpegBands {
  int width = 0, height = 0;
  std::uint32_t header_bytes = 0;             ///< SOI through the end of the SOS segment
  std::vector<std::uint32_t> band_bytes;      ///< each band's entropy-coded bytes, its RSTn included
  std::uint32_t trailer_bytes = 2;            ///< EOI
  int mcus_per_band = 0;                      ///< the restart interval (all MCUs when there is none)
  int mcus_total = 0;
  int mcus_per_row = 0;
  int image_rows_per_mcu_row = 0;             ///< 8 × the largest vertical sampling factor

  std::size_t bands() const { return band_bytes.size(); }
  /// The bands the restart interval gives (what bands() is once the data is scanned).
  std::size_t bandCount() const {
    return mcus_per_band <= 0 ? 0 : (static_cast<std::size_t>(mcus_total) + mcus_per_band - 1) / mcus_per_band;
  }
  /// The band's first byte in the JPEG.
  std::uint32_t bandOffset(std::size_t band) const;
  /// The image rows [first, last) that band covers, whole MCU rows (a band that ends inside
  /// an MCU row covers all of it; the last band ends at the image height).
  std::pair<int, int> bandRows(std::size_t band) const;
};

/// What the header alone says (band_bytes empty, trailer_bytes 2): the geometry and the number
/// of bands, bandCount(). nullopt with *error as for findJpegBands.
std::optional<JpegBands> readJpegBandGeometry(std::span<const std::uint8_t> header, std::string* error);

/// Parses a baseline (SOF0/SOF1, Huffman) single-scan JPEG; nullopt with *error for anything
/// else, for a restart marker out of sequence, or for a band count the restart interval does
/// not give.
std::optional<JpegBands> findJpegBands(std::span<const std::uint8_t> jpeg, std::string* error);

/// Writes band `band` of a JPEG whose header is `header` (header_bytes long, as findJpegBands
/// read it) as all-zero blocks: the JPEG decodes, the band mid grey. Appends to out. False with
/// *error when the header does not parse or its Huffman tables lack the codes needed.
/// `bands` needs its geometry (readJpegBandGeometry), not its band_bytes.
bool appendFillerBand(std::span<const std::uint8_t> header, const JpegBands& bands, std::size_t band,
                      std::vector<std::uint8_t>& out, std::string* error);

}  // namespace telesphere::link::media
