// SPDX-License-Identifier: MIT
/// @brief The byte order of every media datagram (network order, big-endian): the few helpers the
///        datagram formats share (media_packet, receiver_report).
#pragma once

#include <cstdint>
#include <vector>

namespace telesphere::link::media::big_endian {

inline void put16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}
inline void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  put16(out, static_cast<std::uint16_t>(v >> 16));
  put16(out, static_cast<std::uint16_t>(v));
}
inline std::uint16_t get16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }
inline std::uint32_t get32(const std::uint8_t* p) { return std::uint32_t{get16(p)} << 16 | get16(p + 2); }

}  // namespace telesphere::link::media::big_endian
