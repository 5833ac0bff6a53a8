// Decoding: the header checks (magic, version, size limit, CRC-32C) and then every payload field
// (ids against the catalog, statuses, reserved bits, finite values, UTF-8 text, no trailing
// bytes); the first problem is described in DecodeResult::detail.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "wire/byte_io.hpp"
#include "meter/protocol/wire.hpp"
#include "wire/wire_checks.hpp"

namespace meter::protocol {
namespace {

using detail::Reader;
using detail::valid_status;

bool known_type(std::uint8_t t) {
  return t >= static_cast<std::uint8_t>(MessageType::Hello) && t <= static_cast<std::uint8_t>(MessageType::Catalog);
}


// A text field of `len` bytes: it must fit in the payload and be valid UTF-8.
bool read_text(Reader& r, std::size_t len, std::string& text, const char* what, std::string& detail) {
  if (!r.text(len, text)) {
    detail = std::string(what) + " runs past the end of the payload";
    return false;
  }
  if (!is_valid_utf8(text)) {
    detail = std::string(what) + " is not valid UTF-8";
    return false;
  }
  return true;
}

bool decode_updates(Reader& r, std::uint8_t& flags, std::vector<SignalUpdate>& out, std::string& detail) {
  std::uint8_t reserved = 0;
  std::uint16_t count = 0;
  if (!r.u8(flags) || !r.u8(reserved) || !r.u16(count)) {
    detail = "update list header needs 4 bytes";
    return false;
  }
  if (reserved != 0) {
    detail = "update list reserved byte is " + std::to_string(reserved) + ", expected 0";
    return false;
  }
  // Each entry takes at least 12 bytes: reject absurd counts before reserving memory.
  if (static_cast<std::size_t>(count) * 12 > r.remaining()) {
    detail = "count " + std::to_string(count) + " needs at least " + std::to_string(count * 12) +
             " bytes, only " + std::to_string(r.remaining()) + " left";
    return false;
  }
  out.clear();
  out.reserve(count);
  for (std::uint16_t i = 0; i < count; ++i) {
    SignalUpdate u;
    std::uint8_t status = 0, eflags = 0;
    // Built only on the error path: the happy path allocates nothing per entry.
    const auto where = [i] { return "entry " + std::to_string(i) + ": "; };
    if (!r.u16(u.id) || !r.u8(status) || !r.u8(eflags) || !r.f64(u.value)) {
      detail = where() + "truncated (12 bytes expected)";
      return false;
    }
    if (find_signal(u.id) == nullptr) {
      detail = where() + "unknown signal id " + std::to_string(u.id);
      return false;
    }
    if (!valid_status(status)) {
      detail = where() + "status " + std::to_string(status) + " is not 0..3";
      return false;
    }
    u.status = static_cast<SignalStatus>(status);
    if ((eflags & ~1U) != 0) {
      detail = where() + "entry flags " + std::to_string(eflags) + " use reserved bits (only bit 0 is defined)";
      return false;
    }
    if (!std::isfinite(u.value)) {
      detail = where() + "value is not finite (signal " + std::to_string(u.id) + ")";
      return false;
    }
    u.has_text = (eflags & 1U) != 0;
    if (u.has_text) {
      std::uint8_t len = 0;
      if (!r.u8(len) || !r.text(len, u.text)) {
        detail = where() + "text runs past the end of the payload";
        return false;
      }
      if (!is_valid_utf8(u.text)) {
        detail = where() + "text is not valid UTF-8";
        return false;
      }
    }
    out.push_back(std::move(u));
  }
  return true;
}

// HELLO: role, flags, protocol version, catalog hash and size, heartbeat period, name, catalog source.
bool decode_hello(Reader& r, std::size_t size, Message& out, std::string& detail) {
  Hello h;
  std::uint8_t role = 0, name_len = 0, source_len = 0;
  if (!r.u8(role) || !r.u8(h.flags) || !r.u16(h.protocol_version) || !r.u64(h.catalog_hash) ||
      !r.u16(h.signal_count) || !r.u32(h.heartbeat_period_ms) || !r.u8(name_len)) {
    detail = "HELLO needs at least 20 bytes, got " + std::to_string(size);
    return false;
  }
  if (role != 1 && role != 2) {
    detail = "HELLO role " + std::to_string(role) + " is not 1 (publisher) or 2 (subscriber)";
    return false;
  }
  if ((h.flags & ~kHelloTakesCatalog) != 0) {
    detail = "HELLO flags " + std::to_string(h.flags) + " use reserved bits (only bit 0 is defined)";
    return false;
  }
  if (name_len > kMaxNameBytes) {
    detail = "HELLO name length " + std::to_string(name_len) + " exceeds " + std::to_string(kMaxNameBytes);
    return false;
  }
  if (!read_text(r, name_len, h.name, "HELLO name", detail)) return false;
  if (!r.u8(source_len)) {
    detail = "HELLO catalog source length missing after the name";
    return false;
  }
  if (!read_text(r, source_len, h.catalog_source, "HELLO catalog source", detail)) return false;
  if (!r.u32(h.key_id)) {
    detail = "HELLO key id missing after the catalog source";
    return false;
  }
  for (auto& b : h.nonce) {
    if (!r.u8(b)) {
      detail = "HELLO nonce needs " + std::to_string(kNonceSize) + " bytes after the key id";
      return false;
    }
  }
  h.role = static_cast<Role>(role);
  out = std::move(h);
  return true;
}

// CLOSE: the reason and its text.
bool decode_close(Reader& r, Message& out, std::string& detail) {
  Close c;
  std::uint8_t reason = 0, len = 0;
  if (!r.u8(reason) || !r.u8(len)) {
    detail = "CLOSE needs at least 2 bytes";
    return false;
  }
  if (reason > static_cast<std::uint8_t>(CloseReason::Authentication)) {
    detail = "CLOSE reason " + std::to_string(reason) + " is not 0..7";
    return false;
  }
  if (!read_text(r, len, c.text, "CLOSE text", detail)) return false;
  c.reason = static_cast<CloseReason>(reason);
  out = std::move(c);
  return true;
}

bool decode_payload(std::uint8_t type, std::span<const std::uint8_t> payload, Message& out,
                    std::string& detail) {
  Reader r(payload);
  switch (static_cast<MessageType>(type)) {
    case MessageType::Hello:
      if (!decode_hello(r, payload.size(), out, detail)) return false;
      break;
    case MessageType::Snapshot: {
      Snapshot s;
      std::uint8_t flags = 0;
      if (!decode_updates(r, flags, s.signals, detail)) {
        detail = "SNAPSHOT " + detail;
        return false;
      }
      if ((flags & ~1U) != 0) {
        detail = "SNAPSHOT flags use reserved bits";
        return false;
      }
      s.complete = (flags & 1U) != 0;
      out = std::move(s);
      break;
    }
    case MessageType::Delta: {
      Delta d;
      std::uint8_t flags = 0;
      if (!decode_updates(r, flags, d.signals, detail)) {
        detail = "DELTA " + detail;
        return false;
      }
      if (flags != 0) {
        detail = "DELTA flags must be 0";
        return false;
      }
      out = std::move(d);
      break;
    }
    case MessageType::Heartbeat:
      out = Heartbeat{};
      break;
    case MessageType::Status: {
      Status s;
      if (!r.u64(s.frames_rendered) || !r.u64(s.last_sequence_applied) || !r.u32(s.fault_flags)) {
        detail = "STATUS needs 20 bytes, got " + std::to_string(payload.size());
        return false;
      }
      out = s;
      break;
    }
    case MessageType::Close:
      if (!decode_close(r, out, detail)) return false;
      break;
    case MessageType::Catalog: {
      CatalogChunk c;
      std::uint32_t len = 0;
      if (!r.u64(c.catalog_hash) || !r.u16(c.index) || !r.u16(c.count) || !r.u32(len)) {
        detail = "CATALOG needs at least 16 bytes, got " + std::to_string(payload.size());
        return false;
      }
      if (c.count == 0 || c.index >= c.count) {
        detail = "CATALOG piece " + std::to_string(c.index) + " of " + std::to_string(c.count) +
                 ": index must be below count";
        return false;
      }
      if (len != r.remaining()) {
        detail = "CATALOG length " + std::to_string(len) + " does not match the " + std::to_string(r.remaining()) +
                 " byte(s) that follow";
        return false;
      }
      r.text(len, c.bytes);  // JSON is checked when the pieces are assembled and parsed
      out = std::move(c);
      break;
    }
    default:
      detail = "unknown message type";  // caller checked; kept for completeness
      return false;
  }
  if (r.remaining() != 0) {
    detail = std::string(to_string(static_cast<MessageType>(type))) + " has " +
             std::to_string(r.remaining()) + " trailing byte(s) after the last field";
    return false;
  }
  return true;
}

}  // namespace

DecodeResult peek_header(std::span<const std::uint8_t> bytes) {
  DecodeResult res;
  // Judge the magic and version as soon as their bytes are here, so a stream of garbage (say an
  // HTTP request sent to the port) is refused at once instead of after a handshake timeout.
  const std::uint8_t magic_bytes[4] = {static_cast<std::uint8_t>(kMagic), static_cast<std::uint8_t>(kMagic >> 8),
                                       static_cast<std::uint8_t>(kMagic >> 16), static_cast<std::uint8_t>(kMagic >> 24)};
  for (std::size_t i = 0; i < std::min<std::size_t>(4, bytes.size()); ++i) {
    if (bytes[i] != magic_bytes[i]) {
      res.error = DecodeError::BadMagic;
      res.detail = "byte " + std::to_string(i) + " of the magic is " + std::to_string(bytes[i]) +
                   ", expected \"MTRL\" (4D 54 52 4C)";
      return res;
    }
  }
  if (bytes.size() > 4 && bytes[4] != kProtocolVersion) {
    res.header.version = bytes[4];
    res.error = DecodeError::BadVersion;
    res.detail = "protocol version " + std::to_string(bytes[4]) + ", this build speaks " +
                 std::to_string(kProtocolVersion);
    return res;
  }
  if (bytes.size() < kHeaderSize) {
    res.error = DecodeError::Truncated;
    res.detail = "header needs " + std::to_string(kHeaderSize) + " bytes, got " + std::to_string(bytes.size());
    return res;
  }
  Reader r(bytes);
  std::uint32_t magic = 0;
  std::uint64_t ts = 0;
  r.u32(magic);
  r.u8(res.header.version);
  r.u8(res.header.type);
  r.u16(res.header.flags);
  r.u32(res.header.payload_length);
  r.u64(res.header.sequence);
  r.u64(ts);
  r.u32(res.header.crc);
  res.header.timestamp_ns = static_cast<std::int64_t>(ts);
  if (magic != kMagic) {
    res.error = DecodeError::BadMagic;
    char buf[64];
    std::snprintf(buf, sizeof buf, "magic is 0x%08X, expected 0x%08X (\"MTRL\")", magic, kMagic);
    res.detail = buf;
    return res;
  }
  if (res.header.version != kProtocolVersion) {
    res.error = DecodeError::BadVersion;
    res.detail = "protocol version " + std::to_string(res.header.version) + ", this build speaks " +
                 std::to_string(kProtocolVersion);
    return res;
  }
  if (res.header.payload_length > kMaxPayloadSize) {
    res.error = DecodeError::Oversized;
    res.detail = "payload length " + std::to_string(res.header.payload_length) + " exceeds the limit of " +
                 std::to_string(kMaxPayloadSize);
    return res;
  }
  res.frame_size = kHeaderSize + res.header.payload_length + (res.header.tagged() ? kTagSize : 0);
  return res;
}

DecodeResult decode(std::span<const std::uint8_t> bytes) {
  DecodeResult res = peek_header(bytes);
  if (res.error != DecodeError::None) return res;
  if (bytes.size() < res.frame_size) {
    res.error = DecodeError::Truncated;
    res.detail = "frame needs " + std::to_string(res.frame_size) + " bytes, got " + std::to_string(bytes.size());
    return res;
  }
  const auto payload = bytes.subspan(kHeaderSize, res.header.payload_length);
  std::uint32_t crc = crc32c(bytes.first(28));
  crc = crc32c(payload, crc);
  if (crc != res.header.crc) {
    res.error = DecodeError::BadCrc;
    char buf[80];
    std::snprintf(buf, sizeof buf, "CRC-32C is 0x%08X, header says 0x%08X", crc, res.header.crc);
    res.detail = buf;
    return res;
  }
  if (!known_type(res.header.type)) {
    res.error = DecodeError::UnknownType;
    res.detail = "message type " + std::to_string(res.header.type) + " is not 1..7";
    return res;
  }
  if ((res.header.flags & ~kFrameTagged) != 0) {
    res.error = DecodeError::Malformed;
    res.detail = "header flags are " + std::to_string(res.header.flags) + ", only bit 0 (tagged) is defined";
    return res;
  }
  std::string detail;
  if (!decode_payload(res.header.type, payload, res.frame.message, detail)) {
    res.error = DecodeError::Malformed;
    res.detail = std::move(detail);
    return res;
  }
  res.frame.sequence = res.header.sequence;
  res.frame.timestamp_ns = res.header.timestamp_ns;
  res.bytes = bytes.first(res.frame_size);
  return res;
}

}  // namespace meter::protocol
