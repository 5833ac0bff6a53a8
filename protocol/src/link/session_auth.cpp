#include "link/session_auth.hpp"

#include <variant>

namespace meter::protocol::detail {
namespace {

Role other(Role r) { return r == Role::Publisher ? Role::Subscriber : Role::Publisher; }

}  // namespace

SessionAuth::SessionAuth(const KeyRing& keys, Role own_role)
    : keys_(&keys), own_role_(own_role), own_key_(keys.current()), nonce_(fresh_nonce()),
      hello_key_(derive_hello_key(own_key_.key, own_role)) {}

std::string SessionAuth::start(const Hello& peer) {
  if (peer.key_id == 0) {
    return "peer " + (peer.name.empty() ? std::string("(unnamed)") : peer.name) +
           " does not authenticate (no key file); this end requires a MAC with a key from " + keys_->path();
  }
  const FrameKey* peer_key = keys_->find(peer.key_id);
  if (peer_key == nullptr) {
    return "peer tags with key id " + std::to_string(peer.key_id) + ", which " + keys_->path() +
           " does not hold (it holds " + keys_->ids() + ")";
  }
  const Nonce& pub = own_role_ == Role::Publisher ? nonce_ : peer.nonce;
  const Nonce& sub = own_role_ == Role::Publisher ? peer.nonce : nonce_;
  tx_ = derive_session_key(own_key_.key, own_role_, pub, sub);
  rx_ = derive_session_key(*peer_key, other(own_role_), pub, sub);
  peer_key_id_ = peer.key_id;
  return {};
}

void SessionAuth::announce(Hello& hello) const {
  hello.key_id = own_key_.id;
  hello.nonce = nonce_;
}

bool SessionAuth::keys_held() const {
  return keys_->find(own_key_.id) != nullptr && (!rx_ || keys_->find(peer_key_id_) != nullptr);
}

std::string start_session(FrameGuard* guard, const Hello& peer) {
  if (guard != nullptr) return guard->start(peer);
  if (peer.key_id == 0) return {};
  return "peer authenticates with key id " + std::to_string(peer.key_id) +
         " but this end has no key file: give both ends the same key file (--key-file)";
}

const FrameKey* SessionAuth::tx_key(MessageType type) const {
  if (tx_) return &*tx_;
  return type == MessageType::Hello ? &hello_key_ : nullptr;  // a refusal before the session: untagged CLOSE
}

DecodeError SessionAuth::check(const DecodeResult& frame, std::string& detail, bool& fatal) const {
  const auto type = static_cast<MessageType>(frame.header.type);
  if (type == MessageType::Hello && !rx_) {
    const auto& hello = std::get<Hello>(frame.frame.message);
    if (!frame.header.tagged()) {
      if (hello.key_id == 0) return DecodeError::None;  // start() refuses it with the reason
      detail = "HELLO names key " + std::to_string(hello.key_id) + " but carries no tag";
      fatal = true;
      return DecodeError::MissingMac;
    }
    const FrameKey* key = keys_->find(hello.key_id);
    if (key == nullptr) return DecodeError::None;  // start() refuses it naming the keys held
    if (!frame_tag_matches(frame.bytes, derive_hello_key(*key, other(own_role_)))) {
      detail = "HELLO tag does not verify with key " + std::to_string(hello.key_id) + " of " + keys_->path() +
               ": the two ends hold different keys under that id, or the HELLO was altered";
      fatal = true;
      return DecodeError::BadMac;
    }
    return DecodeError::None;
  }
  if (!rx_) return DecodeError::None;  // before the peer's HELLO only HELLO or CLOSE is taken
  if (!frame.header.tagged()) {
    // A CLOSE can only end the connection, which anyone on the path can do anyway; a peer that
    // refuses us before it has our keys sends it untagged. The link logs it as unauthenticated.
    if (type == MessageType::Close) return DecodeError::None;
    detail = std::string(to_string(type)) + " seq " + std::to_string(frame.header.sequence) +
             " has no MAC on an authenticated link (stripped, or sent by an unauthenticated peer)";
    return DecodeError::MissingMac;
  }
  if (!frame_tag_matches(frame.bytes, *rx_)) {
    detail = std::string(to_string(type)) + " seq " + std::to_string(frame.header.sequence) +
             ": MAC does not verify (altered, forged, or from another connection or direction)";
    return DecodeError::BadMac;
  }
  return DecodeError::None;
}

}  // namespace meter::protocol::detail
