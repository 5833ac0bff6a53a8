// What a Channel asks about authentication, per frame, without knowing keys or handshakes: the key
// to tag an outgoing frame with, and whether a received frame's tag is acceptable. A channel with a
// guard also takes sequence numbers strictly (an old one is a replay, a skipped one a drop).
#pragma once

#include <string>

#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

class FrameGuard {
 public:
  virtual ~FrameGuard() = default;
  // nullptr: send the frame untagged.
  virtual const FrameKey* tx_key(MessageType type) const = 0;
  // DecodeError::None to accept, BadMac / MissingMac to drop (with `detail`); `fatal` set when
  // the connection must close (a HELLO that does not verify).
  virtual DecodeError check(const DecodeResult& frame, std::string& detail, bool& fatal) const = 0;
  // The handshake's part: what this end's HELLO announces (key id, nonce), and taking the peer's
  // HELLO ("" or the refusal text).
  virtual void announce(Hello& hello) const = 0;
  virtual std::string start(const Hello& peer) = 0;
  // False once a key this connection uses was removed from the key file (revoked).
  virtual bool keys_held() const = 0;
};

}  // namespace meter::protocol::detail
