// The frame codec: 32-byte header (magic, version, type, length, sequence, timestamp, CRC-32C)
// around a payload, encoded and decoded as pure functions on byte spans.
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "byte_io.hpp"
#include "meter/protocol/wire.hpp"
#include "payload.hpp"

namespace meter::protocol {
namespace {

using detail::Reader;
using detail::Writer;
using detail::decode_payload;
using detail::encode_payload;

bool known_type(std::uint8_t t) {
  return t >= static_cast<std::uint8_t>(MessageType::Hello) && t <= static_cast<std::uint8_t>(MessageType::Close);
}

}  // namespace

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
