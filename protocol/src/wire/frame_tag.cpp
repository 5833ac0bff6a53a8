// The link's MAC: libsodium's keyed BLAKE2b (crypto_generichash), its constant-time compare
// (sodium_memcmp) and its random bytes. Only the inputs' layout is ours.
#include "meter/protocol/frame_tag.hpp"

#include <sodium.h>

#include <stdexcept>
#include <string_view>

namespace meter::protocol {
namespace {

// sodium_init picks the fastest BLAKE2b for this CPU and seeds the random source; it is
// idempotent and thread-safe, so every entry point may call it.
void ensure_sodium() {
  static const bool ready = sodium_init() >= 0;
  if (!ready) throw std::runtime_error("libsodium failed to initialise (sodium_init)");
}

// Keyed BLAKE2b-256 of label | role | the nonces: the derivation of every key the link uses.
FrameKey derive(const FrameKey& key, std::string_view label, Role role, const Nonce* a, const Nonce* b) {
  ensure_sodium();
  crypto_generichash_state state;
  crypto_generichash_init(&state, key.bytes.data(), key.bytes.size(), kLinkKeySize);
  crypto_generichash_update(&state, reinterpret_cast<const unsigned char*>(label.data()), label.size());
  const auto r = static_cast<unsigned char>(role);
  crypto_generichash_update(&state, &r, 1);
  if (a != nullptr) crypto_generichash_update(&state, a->data(), a->size());
  if (b != nullptr) crypto_generichash_update(&state, b->data(), b->size());
  FrameKey out;
  crypto_generichash_final(&state, out.bytes.data(), out.bytes.size());
  return out;
}

}  // namespace

FrameKey derive_hello_key(const FrameKey& link_key, Role sender) {
  return derive(link_key, "meter-link/3 hello", sender, nullptr, nullptr);
}

FrameKey derive_session_key(const FrameKey& link_key, Role sender, const Nonce& publisher_nonce,
                            const Nonce& subscriber_nonce) {
  return derive(link_key, "meter-link/3 session", sender, &publisher_nonce, &subscriber_nonce);
}

std::array<std::uint8_t, kTagSize> frame_tag(std::span<const std::uint8_t> frame, const FrameKey& key) {
  static_assert(kTagSize >= crypto_generichash_BYTES_MIN && kTagSize <= crypto_generichash_BYTES_MAX);
  ensure_sodium();
  std::array<std::uint8_t, kTagSize> tag{};
  crypto_generichash(tag.data(), tag.size(), frame.data(), frame.size(), key.bytes.data(), key.bytes.size());
  return tag;
}

bool frame_tag_matches(std::span<const std::uint8_t> frame, const FrameKey& key) {
  if (frame.size() < kHeaderSize + kTagSize) return false;
  const auto flags = static_cast<std::uint16_t>(frame[6] | (frame[7] << 8));
  if ((flags & kFrameTagged) == 0) return false;
  const auto body = frame.first(frame.size() - kTagSize);
  const auto expected = frame_tag(body, key);
  return sodium_memcmp(expected.data(), frame.data() + body.size(), kTagSize) == 0;
}

Nonce fresh_nonce() {
  ensure_sodium();
  Nonce n{};
  randombytes_buf(n.data(), n.size());
  return n;
}

}  // namespace meter::protocol
