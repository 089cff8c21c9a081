// SPDX-License-Identifier: MIT
/// @brief The media path sealed (DESIGN.md §10): every UDP datagram, both ways, encrypted and
///        authenticated with libsodium's ChaCha20-Poly1305 (IETF AEAD) under a session key the
///        robot makes per operator session and hands over the authenticated, encrypted ZeroMQ
///        control channel (ControlRequest.open_media_session). No cryptography of ours: the
///        nonce is the direction and a per-direction counter that never repeats under one key,
///        and the receiving end refuses a counter it has seen (a sliding window of 4096), so a
///        recorded datagram cannot be played again.
///        Wire: [0xE5][direction][counter, 8 bytes big-endian][ciphertext][16-byte tag]; the ten
///        header bytes are authenticated too.
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace telesphere::link::media {

using MediaSealKey = std::array<std::uint8_t, 32>;

inline constexpr std::uint8_t kSealMarker = 0xE5;
inline constexpr std::size_t kSealHeaderBytes = 10;
inline constexpr std::size_t kSealTagBytes = 16;
inline constexpr std::size_t kSealOverheadBytes = kSealHeaderBytes + kSealTagBytes;

/// Which way a datagram goes: each direction has its own counter, so the two never share a nonce.
enum class SealDirection : std::uint8_t { kToReceiver = 1, kToSender = 2 };

/// A new random session key (libsodium's randombytes).
MediaSealKey newMediaSealKey();

/// Seals the datagrams one end sends. Not thread-safe: one per sending thread and direction.
class MediaSealer {
 public:
  MediaSealer(const MediaSealKey& key, SealDirection direction);
  /// `out` = the sealed `plain` (plain.size() + kSealOverheadBytes).
  void seal(std::span<const std::uint8_t> plain, std::vector<std::uint8_t>& out);
  std::uint64_t sealed() const { return counter_; }

 private:
  MediaSealKey key_;
  SealDirection direction_;
  std::uint64_t counter_ = 0;
};

enum class SealRefusal { kNone, kNotSealed, kWrongDirection, kForged, kReplayed, kTooOld };
std::string_view sealRefusalName(SealRefusal why);

/// Opens the datagrams the other end sealed: forged, replayed or out-of-window ones are refused.
class MediaOpener {
 public:
  static constexpr std::uint64_t kWindow = 4096;

  MediaOpener(const MediaSealKey& key, SealDirection direction);
  /// `plain` = the opened datagram; false with the reason (`plain` then holds nothing of use).
  bool open(std::span<const std::uint8_t> sealed, std::vector<std::uint8_t>& plain, SealRefusal* why);

 private:
  MediaSealKey key_;
  SealDirection direction_;
  std::uint64_t highest_ = 0;      ///< the highest counter opened (0: none yet)
  std::bitset<kWindow> seen_;      ///< bit (counter % kWindow) for the counters in (highest - kWindow, highest]
};

}  // namespace telesphere::link::media
