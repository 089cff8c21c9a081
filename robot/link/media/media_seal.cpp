// SPDX-License-Identifier: MIT
/// @brief Sealing the media path with libsodium (see media_seal.h).
#include "robot/link/media/media_seal.h"

#include <sodium.h>

#include <stdexcept>

namespace telesphere::link::media {
namespace {

void ensureSodium() {
  // sodium_init is thread-safe and idempotent; < 0 means the library cannot be used at all.
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

void nonceOf(SealDirection direction, std::uint64_t counter, unsigned char* nonce) {
  static_assert(crypto_aead_chacha20poly1305_IETF_NPUBBYTES == 12);
  nonce[0] = static_cast<unsigned char>(direction);
  nonce[1] = nonce[2] = nonce[3] = 0;
  for (int i = 0; i < 8; ++i) nonce[4 + i] = static_cast<unsigned char>(counter >> (56 - 8 * i));
}

}  // namespace

MediaSealKey newMediaSealKey() {
  ensureSodium();
  static_assert(crypto_aead_chacha20poly1305_IETF_KEYBYTES == 32);
  MediaSealKey key;
  crypto_aead_chacha20poly1305_ietf_keygen(key.data());
  return key;
}

std::string_view sealRefusalName(SealRefusal why) {
  switch (why) {
    case SealRefusal::kNone: return "none";
    case SealRefusal::kNotSealed: return "not sealed";
    case SealRefusal::kWrongDirection: return "wrong direction";
    case SealRefusal::kForged: return "forged or another key";
    case SealRefusal::kReplayed: return "replayed";
    case SealRefusal::kTooOld: return "older than the replay window";
  }
  return "unknown";
}

MediaSealer::MediaSealer(const MediaSealKey& key, SealDirection direction) : key_(key), direction_(direction) {
  ensureSodium();
}

void MediaSealer::seal(std::span<const std::uint8_t> plain, std::vector<std::uint8_t>& out) {
  static_assert(crypto_aead_chacha20poly1305_IETF_ABYTES == kSealTagBytes);
  const std::uint64_t counter = ++counter_;
  out.resize(kSealHeaderBytes + plain.size() + kSealTagBytes);
  out[0] = kSealMarker;
  out[1] = static_cast<std::uint8_t>(direction_);
  for (int i = 0; i < 8; ++i) out[2 + i] = static_cast<std::uint8_t>(counter >> (56 - 8 * i));
  unsigned char nonce[12];
  nonceOf(direction_, counter, nonce);
  unsigned long long length = 0;
  crypto_aead_chacha20poly1305_ietf_encrypt(out.data() + kSealHeaderBytes, &length, plain.data(), plain.size(),
                                            out.data(), kSealHeaderBytes, nullptr, nonce, key_.data());
  out.resize(kSealHeaderBytes + length);
}

MediaOpener::MediaOpener(const MediaSealKey& key, SealDirection direction) : key_(key), direction_(direction) {
  ensureSodium();
}

bool MediaOpener::open(std::span<const std::uint8_t> sealed, std::vector<std::uint8_t>& plain, SealRefusal* why) {
  if (sealed.size() < kSealOverheadBytes || sealed[0] != kSealMarker) {
    *why = SealRefusal::kNotSealed;
    return false;
  }
  if (sealed[1] != static_cast<std::uint8_t>(direction_)) {
    *why = SealRefusal::kWrongDirection;
    return false;
  }
  std::uint64_t counter = 0;
  for (int i = 0; i < 8; ++i) counter = (counter << 8) | sealed[2 + std::size_t(i)];
  // Cheap checks before the cryptography: a counter we know is refused without decrypting.
  if (counter == 0 || (highest_ >= kWindow && counter <= highest_ - kWindow)) {
    *why = SealRefusal::kTooOld;
    return false;
  }
  if (counter <= highest_ && seen_[counter % kWindow]) {
    *why = SealRefusal::kReplayed;
    return false;
  }
  unsigned char nonce[12];
  nonceOf(direction_, counter, nonce);
  // Straight into the caller's buffer (reused datagram after datagram: no allocation per datagram).
  plain.resize(sealed.size() - kSealOverheadBytes);
  unsigned long long length = 0;
  if (crypto_aead_chacha20poly1305_ietf_decrypt(plain.data(), &length, nullptr, sealed.data() + kSealHeaderBytes,
                                                sealed.size() - kSealHeaderBytes, sealed.data(), kSealHeaderBytes,
                                                nonce, key_.data()) != 0) {
    *why = SealRefusal::kForged;
    return false;
  }
  // Only an authentic datagram moves the window.
  if (counter > highest_) {
    const std::uint64_t advance = counter - highest_;
    if (advance >= kWindow) {
      seen_.reset();
    } else {
      for (std::uint64_t c = highest_ + 1; c < counter; ++c) seen_[c % kWindow] = false;
    }
    highest_ = counter;
  }
  seen_[counter % kWindow] = true;
  plain.resize(length);
  *why = SealRefusal::kNone;
  return true;
}

}  // namespace telesphere::link::media
