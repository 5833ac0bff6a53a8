// Encoding: a Message into one frame (32-byte header, payload, CRC-32C). Every field the decoder
// would reject is refused here first, so the encoder never produces a frame the decoder rejects.
// The payload writers live in this file with the frame writer so the whole encode inlines.
#include <cmath>
#include <stdexcept>
#include <string>

#include "wire/byte_io.hpp"
#include "meter/protocol/frame_tag.hpp"
#include "meter/protocol/wire.hpp"
#include "wire/wire_checks.hpp"

namespace meter::protocol {
namespace {

using detail::valid_status;
using detail::Writer;

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
      check_text("HELLO catalog source", h.catalog_source, kMaxTextBytes);
      if ((h.flags & ~kHelloTakesCatalog) != 0) throw std::invalid_argument("HELLO flags use reserved bits");
      w.u8(static_cast<std::uint8_t>(h.role));
      w.u8(h.flags);
      w.u16(h.protocol_version);
      w.u64(h.catalog_hash);
      w.u16(h.signal_count);
      w.u32(h.heartbeat_period_ms);
      w.u8(static_cast<std::uint8_t>(h.name.size()));
      w.bytes(h.name);
      w.u8(static_cast<std::uint8_t>(h.catalog_source.size()));
      w.bytes(h.catalog_source);
      w.u32(h.key_id);
      for (std::uint8_t b : h.nonce) w.u8(b);
    }
    void operator()(const CatalogChunk& c) const {
      if (c.bytes.size() > kMaxCatalogChunkBytes) throw std::invalid_argument("CATALOG piece exceeds kMaxCatalogChunkBytes");
      if (c.count == 0 || c.index >= c.count) throw std::invalid_argument("CATALOG piece index must be below count");
      w.u64(c.catalog_hash);
      w.u16(c.index);
      w.u16(c.count);
      w.u32(static_cast<std::uint32_t>(c.bytes.size()));
      w.bytes(c.bytes);
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
      if (c.reason > CloseReason::Authentication) throw std::invalid_argument("CLOSE: unknown reason code");
      check_text("CLOSE text", c.text, kMaxTextBytes);
      w.u8(static_cast<std::uint8_t>(c.reason));
      w.u8(static_cast<std::uint8_t>(c.text.size()));
      w.bytes(c.text);
    }
  };
  std::visit(Visitor{w}, m);
}

}  // namespace

std::size_t encoded_size(const SignalUpdate& update) {
  return 12 + (update.has_text ? 1 + update.text.size() : 0);
}

void encode(const Frame& frame, std::vector<std::uint8_t>& out, const FrameKey* key) {
  const std::size_t start = out.size();
  Writer w(out);
  w.u32(kMagic);
  w.u8(kProtocolVersion);
  w.u8(static_cast<std::uint8_t>(type_of(frame.message)));
  w.u16(key != nullptr ? kFrameTagged : 0);
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
  if (key != nullptr) {
    const auto tag = frame_tag(std::span(out).subspan(start, kHeaderSize + payload), *key);
    out.insert(out.end(), tag.begin(), tag.end());
  }
}

std::vector<std::uint8_t> encode(const Frame& frame, const FrameKey* key) {
  std::vector<std::uint8_t> out;
  encode(frame, out, key);
  return out;
}

}  // namespace meter::protocol
