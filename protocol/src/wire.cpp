#include "meter/protocol/wire.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace meter::protocol {
namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);

// Little-endian writers/readers built from shifts, so the code is correct on any host byte order.
class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void bytes(std::string_view s) { out_.insert(out_.end(), s.begin(), s.end()); }

 private:
  void put(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> in) : in_(in) {}
  std::size_t remaining() const { return in_.size() - pos_; }
  std::size_t position() const { return pos_; }
  bool u8(std::uint8_t& v) {
    if (remaining() < 1) return false;
    v = in_[pos_++];
    return true;
  }
  bool u16(std::uint16_t& v) { return get(v, 2); }
  bool u32(std::uint32_t& v) { return get(v, 4); }
  bool u64(std::uint64_t& v) { return get(v, 8); }
  bool f64(double& v) {
    std::uint64_t bits = 0;
    if (!u64(bits)) return false;
    v = std::bit_cast<double>(bits);
    return true;
  }
  bool text(std::size_t n, std::string& s) {
    if (remaining() < n) return false;
    s.assign(reinterpret_cast<const char*>(in_.data() + pos_), n);
    pos_ += n;
    return true;
  }

 private:
  template <typename T>
  bool get(T& v, int n) {
    if (remaining() < static_cast<std::size_t>(n)) return false;
    std::uint64_t acc = 0;
    for (int i = 0; i < n; ++i) acc |= static_cast<std::uint64_t>(in_[pos_ + i]) << (8 * i);
    pos_ += static_cast<std::size_t>(n);
    v = static_cast<T>(acc);
    return true;
  }
  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
};

bool valid_status(std::uint8_t s) { return s <= static_cast<std::uint8_t>(SignalStatus::NotAvailable); }

void check_text(std::string_view what, std::string_view text, std::size_t limit) {
  if (text.size() > limit) {
    throw std::invalid_argument(std::string(what) + " is " + std::to_string(text.size()) +
                                " bytes; the wire format allows at most " + std::to_string(limit));
  }
  if (!is_valid_utf8(text)) throw std::invalid_argument(std::string(what) + " is not valid UTF-8");
}

void encode_update(const SignalUpdate& u, Writer& w) {
  if (!std::isfinite(u.value)) {
    throw std::invalid_argument("signal " + std::to_string(u.id) +
                                ": value is not finite; send status invalid with a finite value");
  }
  if (!valid_status(static_cast<std::uint8_t>(u.status))) {
    throw std::invalid_argument("signal " + std::to_string(u.id) + ": unknown status " +
                                std::to_string(static_cast<unsigned>(u.status)));
  }
  if (u.has_text) check_text("signal " + std::to_string(u.id) + " text", u.text, kMaxTextBytes);
  w.u16(u.id);
  w.u8(static_cast<std::uint8_t>(u.status));
  w.u8(u.has_text ? 1 : 0);
  w.f64(u.value);
  if (u.has_text) {
    w.u8(static_cast<std::uint8_t>(u.text.size()));
    w.bytes(u.text);
  }
}

void encode_updates(std::uint8_t flags, const std::vector<SignalUpdate>& updates, Writer& w) {
  if (updates.size() > 0xFFFF) throw std::length_error("more than 65535 signal updates in one frame");
  w.u8(flags);
  w.u8(0);
  w.u16(static_cast<std::uint16_t>(updates.size()));
  for (const auto& u : updates) encode_update(u, w);
}

void encode_payload(const Message& m, Writer& w) {
  struct Visitor {
    Writer& w;
    void operator()(const Hello& h) const {
      check_text("HELLO name", h.name, kMaxNameBytes);
      if (h.role != Role::Publisher && h.role != Role::Subscriber) {
        throw std::invalid_argument("HELLO role must be publisher (1) or subscriber (2)");
      }
      w.u8(static_cast<std::uint8_t>(h.role));
      w.u8(0);
      w.u16(h.protocol_version);
      w.u64(h.catalog_hash);
      w.u16(h.signal_count);
      w.u32(h.heartbeat_period_ms);
      w.u8(static_cast<std::uint8_t>(h.name.size()));
      w.bytes(h.name);
    }
    void operator()(const Snapshot& s) const { encode_updates(s.complete ? 1 : 0, s.signals, w); }
    void operator()(const Delta& d) const { encode_updates(0, d.signals, w); }
    void operator()(const Heartbeat&) const {}
    void operator()(const Status& s) const {
      w.u64(s.frames_rendered);
      w.u64(s.last_sequence_applied);
      w.u32(s.fault_flags);
    }
    void operator()(const Close& c) const {
      if (c.reason > CloseReason::Timeout) throw std::invalid_argument("CLOSE: unknown reason code");
      check_text("CLOSE text", c.text, kMaxTextBytes);
      w.u8(static_cast<std::uint8_t>(c.reason));
      w.u8(static_cast<std::uint8_t>(c.text.size()));
      w.bytes(c.text);
    }
  };
  std::visit(Visitor{w}, m);
}

// ---- decoding -------------------------------------------------------------------------------

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

bool decode_payload(std::uint8_t type, std::span<const std::uint8_t> payload, Message& out,
                    std::string& detail) {
  Reader r(payload);
  switch (static_cast<MessageType>(type)) {
    case MessageType::Hello: {
      Hello h;
      std::uint8_t role = 0, reserved = 0, name_len = 0;
      if (!r.u8(role) || !r.u8(reserved) || !r.u16(h.protocol_version) || !r.u64(h.catalog_hash) ||
          !r.u16(h.signal_count) || !r.u32(h.heartbeat_period_ms) || !r.u8(name_len)) {
        detail = "HELLO needs at least 19 bytes, got " + std::to_string(payload.size());
        return false;
      }
      if (role != 1 && role != 2) {
        detail = "HELLO role " + std::to_string(role) + " is not 1 (publisher) or 2 (subscriber)";
        return false;
      }
      if (reserved != 0) {
        detail = "HELLO reserved byte is not 0";
        return false;
      }
      if (name_len > kMaxNameBytes) {
        detail = "HELLO name length " + std::to_string(name_len) + " exceeds " + std::to_string(kMaxNameBytes);
        return false;
      }
      if (!r.text(name_len, h.name)) {
        detail = "HELLO name runs past the end of the payload";
        return false;
      }
      if (!is_valid_utf8(h.name)) {
        detail = "HELLO name is not valid UTF-8";
        return false;
      }
      h.role = static_cast<Role>(role);
      out = std::move(h);
      break;
    }
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
    case MessageType::Close: {
      Close c;
      std::uint8_t reason = 0, len = 0;
      if (!r.u8(reason) || !r.u8(len)) {
        detail = "CLOSE needs at least 2 bytes";
        return false;
      }
      if (reason > static_cast<std::uint8_t>(CloseReason::Timeout)) {
        detail = "CLOSE reason " + std::to_string(reason) + " is not 0..6";
        return false;
      }
      if (!r.text(len, c.text)) {
        detail = "CLOSE text runs past the end of the payload";
        return false;
      }
      if (!is_valid_utf8(c.text)) {
        detail = "CLOSE text is not valid UTF-8";
        return false;
      }
      c.reason = static_cast<CloseReason>(reason);
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

bool known_type(std::uint8_t t) {
  return t >= static_cast<std::uint8_t>(MessageType::Hello) && t <= static_cast<std::uint8_t>(MessageType::Close);
}

}  // namespace

bool is_valid_utf8(std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  std::size_t i = 0;
  const std::size_t n = text.size();
  while (i < n) {
    const unsigned char c = s[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    std::uint32_t cp = 0;
    if ((c & 0xE0) == 0xC0) {
      len = 2;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      len = 3;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      len = 4;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + len > n) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((s[i + k] & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (s[i + k] & 0x3F);
    }
    // Reject overlong forms, surrogates and code points past U+10FFFF.
    if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000)) return false;
    if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return false;
    i += len;
  }
  return true;
}

std::string_view to_string(MessageType type) {
  switch (type) {
    case MessageType::Hello: return "HELLO";
    case MessageType::Snapshot: return "SNAPSHOT";
    case MessageType::Delta: return "DELTA";
    case MessageType::Heartbeat: return "HEARTBEAT";
    case MessageType::Status: return "STATUS";
    case MessageType::Close: return "CLOSE";
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
  }
  return "unknown";
}

MessageType type_of(const Message& message) {
  return static_cast<MessageType>(message.index() + 1);  // variant order matches the type codes
}
static_assert(std::variant_size_v<Message> == 6);
static_assert(std::is_same_v<std::variant_alternative_t<0, Message>, Hello> &&
              std::is_same_v<std::variant_alternative_t<5, Message>, Close>);

std::size_t encoded_size(const SignalUpdate& update) {
  return 12 + (update.has_text ? 1 + update.text.size() : 0);
}

void encode(const Frame& frame, std::vector<std::uint8_t>& out) {
  const std::size_t start = out.size();
  Writer w(out);
  w.u32(kMagic);
  w.u8(kProtocolVersion);
  w.u8(static_cast<std::uint8_t>(type_of(frame.message)));
  w.u16(0);
  w.u32(0);  // payload length, patched below
  w.u64(frame.sequence);
  w.u64(static_cast<std::uint64_t>(frame.timestamp_ns));
  w.u32(0);  // CRC, patched below
  try {
    encode_payload(frame.message, w);
  } catch (...) {
    out.resize(start);  // leave `out` as it was: a failed encode never leaves half a frame behind
    throw;
  }
  const std::size_t payload = out.size() - start - kHeaderSize;
  if (payload > kMaxPayloadSize) {
    out.resize(start);
    throw std::length_error(std::string(to_string(type_of(frame.message))) + " payload of " +
                            std::to_string(payload) + " bytes exceeds the limit of " +
                            std::to_string(kMaxPayloadSize));
  }
  for (int i = 0; i < 4; ++i) out[start + 8 + i] = static_cast<std::uint8_t>(payload >> (8 * i));
  std::uint32_t crc = crc32c(std::span(out).subspan(start, 28));
  crc = crc32c(std::span(out).subspan(start + kHeaderSize, payload), crc);
  for (int i = 0; i < 4; ++i) out[start + 28 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
}

std::vector<std::uint8_t> encode(const Frame& frame) {
  std::vector<std::uint8_t> out;
  encode(frame, out);
  return out;
}

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
  res.frame_size = kHeaderSize + res.header.payload_length;
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
    res.detail = "message type " + std::to_string(res.header.type) + " is not 1..6";
    return res;
  }
  if (res.header.flags != 0) {
    res.error = DecodeError::Malformed;
    res.detail = "header flags are " + std::to_string(res.header.flags) + ", expected 0 (reserved)";
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
  return res;
}

}  // namespace meter::protocol

namespace meter::protocol {

void StreamAssembler::append(std::span<const std::uint8_t> bytes) {
  if (broken_) return;
  if (start_ > 0 && start_ >= buffer_.size() / 2) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<DecodeResult> StreamAssembler::next() {
  if (broken_) return std::nullopt;
  const auto avail = std::span<const std::uint8_t>(buffer_).subspan(start_);
  DecodeResult res = peek_header(avail);
  if (res.error == DecodeError::Truncated) return std::nullopt;
  if (res.error == DecodeError::None) {
    if (avail.size() < res.frame_size) return std::nullopt;  // wait for the rest of the payload
    res = decode(avail.first(res.frame_size));
  }
  switch (res.error) {
    case DecodeError::None:
    case DecodeError::UnknownType:
    case DecodeError::Malformed:
      start_ += res.frame_size;  // CRC was good, so the length is trustworthy: skip exactly this frame
      if (start_ == buffer_.size()) {
        buffer_.clear();
        start_ = 0;
      }
      return res;
    default:
      broken_ = true;
      buffer_.clear();
      buffer_.shrink_to_fit();
      start_ = 0;
      return res;
  }
}

}  // namespace meter::protocol
