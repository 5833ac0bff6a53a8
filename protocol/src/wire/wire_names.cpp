// Names of the wire format's enumerations (for logs and error texts) and the message type of a
// Message variant.
#include <type_traits>

#include "meter/protocol/wire.hpp"

namespace meter::protocol {

std::string describe_fault_flags(std::uint32_t flags) {
  if (flags == 0) return "none";
  std::string out;
  for (int bit = 0; bit < 32; ++bit) {
    const std::uint32_t b = 1U << bit;
    if (!(flags & b)) continue;
    if (!out.empty()) out += ", ";
    if (b == kViewFaultFrameDeadline) out += "frame-deadline";
    else if (b == kViewFaultDumpFailed) out += "dump-failed";
    else if (b == kViewFaultIntegrity) out += "integrity";
    else if (b == kViewFaultDisplayFrozen) out += "display-frozen";
    else if (b == kControllerFaultBusWarning) out += "bus-warning";
    else if (b == kControllerFaultBusPassive) out += "bus-passive";
    else if (b == kControllerFaultBusOff) out += "bus-off";
    else if (b == kControllerFaultFramesLost) out += "frames-lost";
    else if (b == kControllerFaultReplaySlip) out += "replay-slip";
    else out += "bit " + std::to_string(bit);
  }
  return out;
}

std::string_view to_string(MessageType type) {
  switch (type) {
    case MessageType::Hello: return "HELLO";
    case MessageType::Snapshot: return "SNAPSHOT";
    case MessageType::Delta: return "DELTA";
    case MessageType::Heartbeat: return "HEARTBEAT";
    case MessageType::Status: return "STATUS";
    case MessageType::Close: return "CLOSE";
    case MessageType::Catalog: return "CATALOG";
  }
  return "UNKNOWN";
}

std::string_view to_string(Role role) {
  switch (role) {
    case Role::Publisher: return "publisher";
    case Role::Subscriber: return "subscriber";
  }
  return "unknown";
}

std::string_view to_string(CloseReason reason) {
  switch (reason) {
    case CloseReason::Normal: return "normal";
    case CloseReason::VersionMismatch: return "protocol version mismatch";
    case CloseReason::CatalogMismatch: return "signal catalog mismatch";
    case CloseReason::RoleMismatch: return "role mismatch";
    case CloseReason::NotAllowed: return "peer uid not allowed";
    case CloseReason::ProtocolError: return "protocol error";
    case CloseReason::Timeout: return "timeout";
    case CloseReason::Authentication: return "authentication failed";
  }
  return "unknown";
}

std::string_view to_string(DecodeError error) {
  switch (error) {
    case DecodeError::None: return "ok";
    case DecodeError::Truncated: return "truncated";
    case DecodeError::BadMagic: return "bad magic";
    case DecodeError::BadVersion: return "unsupported version";
    case DecodeError::Oversized: return "oversized";
    case DecodeError::BadCrc: return "CRC mismatch";
    case DecodeError::UnknownType: return "unknown message type";
    case DecodeError::Malformed: return "malformed payload";
    case DecodeError::BadMac: return "MAC mismatch";
    case DecodeError::MissingMac: return "MAC missing";
  }
  return "unknown";
}

MessageType type_of(const Message& message) {
  return static_cast<MessageType>(message.index() + 1);  // variant order matches the type codes
}
static_assert(std::variant_size_v<Message> == 7);
static_assert(std::is_same_v<std::variant_alternative_t<0, Message>, Hello> &&
              std::is_same_v<std::variant_alternative_t<5, Message>, Close> &&
              std::is_same_v<std::variant_alternative_t<6, Message>, CatalogChunk>);


}  // namespace meter::protocol
