// The link's frame authentication as pure functions on bytes: keyed BLAKE2b (libsodium's
// crypto_generichash) over a frame's header and payload, under a key that only one connection and
// one direction use. Nothing here is hand-written cryptography: the MAC, the key derivation, the
// constant-time comparison and the random nonces are libsodium's.
//
//   link key K (key file, by id)  --derive_hello_key(K, role)--------------> tags that side's HELLO
//   K of the sender, both HELLO nonces --derive_session_key(K, role, ...)--> tags every later frame
//
// A frame's tag covers its 32 header bytes (magic, version, type, flags with the tagged bit, payload
// length, sequence, timestamp, CRC) and its payload; the session key brings in the freshness value
// (the two nonces the HELLOs exchanged) and the direction (the sender's role). So a tag verifies
// only for that message, at that sequence number, on that connection, in that direction.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "meter/protocol/wire.hpp"

namespace meter::protocol {

inline constexpr std::size_t kLinkKeySize = 32;  // 256-bit link keys (key file) and derived keys

struct FrameKey {
  std::array<std::uint8_t, kLinkKeySize> bytes{};
  bool operator==(const FrameKey&) const = default;
};

using Nonce = std::array<std::uint8_t, kNonceSize>;

// The key that tags the HELLO a `sender` role sends, derived from the link key K.
FrameKey derive_hello_key(const FrameKey& link_key, Role sender);
// The key that tags every frame after the HELLOs in the direction `sender` -> its peer: derived
// from the sender's link key and both nonces (the publisher's first).
FrameKey derive_session_key(const FrameKey& link_key, Role sender, const Nonce& publisher_nonce,
                            const Nonce& subscriber_nonce);

// The tag of a frame's header + payload (`frame` without its tag).
std::array<std::uint8_t, kTagSize> frame_tag(std::span<const std::uint8_t> frame, const FrameKey& key);
// True if `frame` (a whole tagged frame: header, payload, tag) carries the right tag; compared in
// constant time. False for an untagged frame or one shorter than a header and a tag.
bool frame_tag_matches(std::span<const std::uint8_t> frame, const FrameKey& key);

// kNonceSize bytes from the system's random source (libsodium's randombytes_buf, getrandom(2)).
Nonce fresh_nonce();

}  // namespace meter::protocol
