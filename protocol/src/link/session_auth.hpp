// One authenticated connection's keys and checks, without I/O: the HELLO this end sends is tagged
// with its hello key; once the peer's HELLO is accepted, start() derives the two session keys
// (this end's and the peer's direction) from the link keys and both nonces, and every later frame
// must carry a tag under the peer's session key. The Channel asks it per frame (FrameGuard).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "link/key_ring.hpp"
#include "meter/protocol/frame_tag.hpp"
#include "transport/frame_guard.hpp"

namespace meter::protocol::detail {

class SessionAuth final : public FrameGuard {
 public:
  // Takes the ring's current key (a rotation later does not change this connection) and draws the
  // connection's nonce. `keys` must outlive this object.
  SessionAuth(const KeyRing& keys, Role own_role);
  std::uint32_t key_id() const { return own_key_.id; }
  const Nonce& nonce() const { return nonce_; }

  // The peer's HELLO was acceptable (version, role): derive the session keys. "" or the refusal
  // text (the peer does not authenticate, or names a key this end does not hold).
  std::string start(const Hello& peer) override;
  void announce(Hello& hello) const override;
  bool keys_held() const override;
  bool started() const { return rx_.has_value(); }
  std::uint32_t peer_key_id() const { return peer_key_id_; }

  const FrameKey* tx_key(MessageType type) const override;
  DecodeError check(const DecodeResult& frame, std::string& detail, bool& fatal) const override;

 private:
  const KeyRing* keys_;
  Role own_role_;
  LinkKey own_key_;
  Nonce nonce_;
  FrameKey hello_key_;
  std::optional<FrameKey> tx_, rx_;
  std::uint32_t peer_key_id_ = 0;
};

// The peer's HELLO on a connection with or without a guard: "" to go on, else the refusal text
// (a peer that authenticates while this end has no key file is refused too: both must agree).
std::string start_session(FrameGuard* guard, const Hello& peer);

}  // namespace meter::protocol::detail
