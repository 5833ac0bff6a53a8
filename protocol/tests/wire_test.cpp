// Pure wire-format tests: every message round trip, the exact header layout, and every class of
// malformed input the decoder must reject without crashing.
#include <gtest/gtest.h>

#include <optional>

#include <cmath>
#include <limits>
#include <string>

#include "meter/protocol/wire.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

using test::put_entry;
using test::put_le;
using test::raw_frame;

std::span<const std::uint8_t> as_bytes(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(Crc32c, StandardCheckValue) {
  EXPECT_EQ(crc32c(as_bytes("123456789")), 0xE3069283U);
  EXPECT_EQ(crc32c(as_bytes("")), 0U);
  // RFC 3720 B.4 vectors: 32 zero bytes and 32 0xFF bytes.
  std::vector<std::uint8_t> zeros(32, 0), ones(32, 0xFF);
  EXPECT_EQ(crc32c(zeros), 0x8A9136AAU);
  EXPECT_EQ(crc32c(ones), 0x62A8AB43U);
}

TEST(Crc32c, IncrementalEqualsWholeAtEverySplit) {
  const std::string text = "The quick brown fox jumps over the lazy dog, twice and more.";
  const std::uint32_t whole = crc32c(as_bytes(text));
  for (std::size_t split = 0; split <= text.size(); ++split) {
    const auto a = as_bytes(text).first(split);
    const auto b = as_bytes(text).subspan(split);
    EXPECT_EQ(crc32c(b, crc32c(a)), whole) << "split at " << split;
  }
}

Frame frame_of(Message m, std::uint64_t seq = 7, std::int64_t ts = 1'234'567'890'123) {
  return Frame{seq, ts, std::move(m)};
}

void expect_round_trip(const Frame& f) {
  const auto bytes = encode(f);
  const DecodeResult r = decode(bytes);
  ASSERT_EQ(r.error, DecodeError::None) << r.detail;
  EXPECT_EQ(r.frame_size, bytes.size());
  EXPECT_EQ(r.frame.sequence, f.sequence);
  EXPECT_EQ(r.frame.timestamp_ns, f.timestamp_ns);
  EXPECT_EQ(r.frame.message, f.message);
  EXPECT_EQ(type_of(r.frame.message), type_of(f.message));
}

TEST(WireRoundTrip, Hello) {
  Hello h;
  h.role = Role::Subscriber;
  h.catalog_hash = 0x0123456789ABCDEFULL;
  h.signal_count = 26;
  h.heartbeat_period_ms = 100;
  h.name = "meter-view \xC3\xA9";  // UTF-8 é
  h.catalog_source = "vehicles/ev/ev.vss.json";
  h.flags = kHelloTakesCatalog;
  expect_round_trip(frame_of(h));
  h.role = Role::Publisher;
  h.name.clear();
  h.catalog_source = std::string(kMaxTextBytes, 'p');
  h.flags = 0;
  expect_round_trip(frame_of(h, 1, -5));
}

TEST(WireRoundTrip, CatalogPieces) {
  expect_round_trip(frame_of(CatalogChunk{0x0123456789ABCDEFULL, 0, 1, R"({"Vehicle": {}})"}));
  expect_round_trip(frame_of(CatalogChunk{1, 2, 3, std::string(kMaxCatalogChunkBytes, 'x')}));
  expect_round_trip(frame_of(CatalogChunk{1, 0, 1, ""}));
  // The encoder refuses what the decoder would reject.
  EXPECT_THROW(encode(frame_of(CatalogChunk{1, 3, 3, "x"})), std::invalid_argument);
  EXPECT_THROW(encode(frame_of(CatalogChunk{1, 0, 0, "x"})), std::invalid_argument);
  EXPECT_THROW(encode(frame_of(CatalogChunk{1, 0, 1, std::string(kMaxCatalogChunkBytes + 1, 'x')})),
               std::invalid_argument);
  Hello h;
  h.flags = 2;
  EXPECT_THROW(encode(frame_of(h)), std::invalid_argument);
}

TEST(WireRoundTrip, SnapshotWithTextAndEveryStatus) {
  Snapshot s;
  s.complete = false;
  s.signals.push_back({sig::kSpeed, SignalStatus::Valid, 88.25, false, ""});
  s.signals.push_back({sig::kEngineSpeed, SignalStatus::TimedOut, -0.0, false, ""});
  s.signals.push_back({sig::kFuelLevel, SignalStatus::Invalid, 1e300, false, ""});
  s.signals.push_back({sig::kCurrentGear, SignalStatus::NotAvailable, 3, true, "D3"});
  s.signals.push_back({sig::kTrip, SignalStatus::Valid, 12.5, true, std::string(kMaxTextBytes, 'x')});
  expect_round_trip(frame_of(s));
  s.complete = true;
  expect_round_trip(frame_of(s));
  expect_round_trip(frame_of(Snapshot{true, {}}));
}

TEST(WireRoundTrip, DeltaHeartbeatStatusClose) {
  expect_round_trip(frame_of(Delta{{{sig::kTurnLeft, SignalStatus::Valid, 1.0, false, ""}}}));
  expect_round_trip(frame_of(Delta{}));
  expect_round_trip(frame_of(Heartbeat{}, std::numeric_limits<std::uint64_t>::max()));
  expect_round_trip(frame_of(Status{123456789012ULL, 42, 0xDEADBEEF}));
  expect_round_trip(frame_of(Close{CloseReason::CatalogMismatch, "catalog hash differs"}));
  expect_round_trip(frame_of(Close{CloseReason::Timeout, ""}));
}

TEST(WireLayout, HeaderBytesMatchTheDocument) {
  // docs/protocol.md, "Frame header": this is the worked example printed there.
  const auto bytes = encode(Frame{0x0102030405060708ULL, 0x1112131415161718LL, Status{1, 2, 3}});
  ASSERT_EQ(bytes.size(), kHeaderSize + 20);
  const std::vector<std::uint8_t> header(bytes.begin(), bytes.begin() + 28);
  const std::vector<std::uint8_t> expected = {
      0x4D, 0x54, 0x52, 0x4C,                          // "MTRL"
      0x03,                                            // version
      0x05,                                            // type STATUS
      0x00, 0x00,                                      // flags
      0x14, 0x00, 0x00, 0x00,                          // payload length 20
      0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // sequence
      0x18, 0x17, 0x16, 0x15, 0x14, 0x13, 0x12, 0x11,  // timestamp
  };
  EXPECT_EQ(header, expected);
  std::uint32_t crc = crc32c(std::span(bytes).first(28));
  crc = crc32c(std::span(bytes).subspan(32), crc);
  EXPECT_EQ(bytes[28] | bytes[29] << 8 | bytes[30] << 16 | static_cast<std::uint32_t>(bytes[31]) << 24, crc);
  // STATUS payload: frames_rendered u64, last_sequence_applied u64, fault_flags u32.
  EXPECT_EQ(bytes[32], 1);
  EXPECT_EQ(bytes[40], 2);
  EXPECT_EQ(bytes[48], 3);
}

TEST(WireLayout, DeltaEntryIs12BytesPlusText) {
  Delta d{{{sig::kSpeed, SignalStatus::Valid, 1.0, false, ""}, {sig::kOdometer, SignalStatus::Valid, 2.0, true, "ab"}}};
  const auto bytes = encode(Frame{1, 0, d});
  EXPECT_EQ(bytes.size(), kHeaderSize + kUpdateListOverhead + 12 + 12 + 1 + 2);
  EXPECT_EQ(encoded_size(d.signals[0]), 12U);
  EXPECT_EQ(encoded_size(d.signals[1]), 15U);
  // entry 0 starts after the 4-byte list header: id 1 LE, status 0, flags 0, 1.0 as binary64 LE.
  const std::size_t e = kHeaderSize + 4;
  EXPECT_EQ(bytes[e], 1);
  EXPECT_EQ(bytes[e + 1], 0);
  EXPECT_EQ(bytes[e + 11], 0x3F);  // 1.0 = 0x3FF0000000000000
  EXPECT_EQ(bytes[e + 10], 0xF0);
}

TEST(WireEncode, RefusesWhatTheDecoderWouldReject) {
  std::vector<std::uint8_t> out = {0xAA};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(encode(Frame{1, 0, Delta{{{sig::kSpeed, SignalStatus::Valid, nan, false, ""}}}}, out),
               std::invalid_argument);
  EXPECT_THROW(encode(Frame{1, 0, Delta{{{sig::kSpeed, SignalStatus::Valid, INFINITY, false, ""}}}}, out),
               std::invalid_argument);
  EXPECT_THROW(encode(Frame{1, 0, Delta{{{sig::kSpeed, SignalStatus::Valid, 1, true, std::string(256, 'a')}}}}, out),
               std::invalid_argument);
  EXPECT_THROW(encode(Frame{1, 0, Delta{{{sig::kSpeed, SignalStatus::Valid, 1, true, "\xFF"}}}}, out),
               std::invalid_argument);
  EXPECT_THROW(encode(Frame{1, 0, Delta{{{sig::kSpeed, static_cast<SignalStatus>(9), 1, false, ""}}}}, out),
               std::invalid_argument);
  Hello h;
  h.name = std::string(kMaxNameBytes + 1, 'n');
  EXPECT_THROW(encode(Frame{1, 0, h}, out), std::invalid_argument);
  Delta big;
  big.signals.assign(kMaxPayloadSize / 12 + 1, SignalUpdate{sig::kSpeed, SignalStatus::Valid, 1, false, ""});
  EXPECT_THROW(encode(Frame{1, 0, big}, out), std::length_error);
  // A failed encode leaves the output buffer as it was.
  EXPECT_EQ(out, std::vector<std::uint8_t>{0xAA});
}

// ---- malformed input, one class at a time ------------------------------------------------

std::vector<std::uint8_t> valid_delta_payload() {
  std::vector<std::uint8_t> p = {0, 0};
  put_le(p, 1, 2);
  put_entry(p, sig::kSpeed, 0, 50.0);
  return p;
}

TEST(WireDecode, EveryPrefixOfAValidFrameIsTruncated) {
  const auto bytes = encode(Frame{3, 4, Snapshot{true, {{sig::kSpeed, SignalStatus::Valid, 1, true, "abc"}}}});
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const auto r = decode(std::span(bytes).first(n));
    EXPECT_EQ(r.error, DecodeError::Truncated) << "prefix " << n;
    EXPECT_FALSE(r.detail.empty());
  }
}

TEST(WireDecode, BadMagic) {
  const auto f = raw_frame(3, valid_delta_payload(), 1, kProtocolVersion, 0, 0x4C52544EU);
  const auto r = decode(f);
  EXPECT_EQ(r.error, DecodeError::BadMagic);
  EXPECT_NE(r.detail.find("magic"), std::string::npos);
}

TEST(WireDecode, GarbageIsRefusedAsSoonAsTheMagicDiffers) {
  const std::string http = "GET / HTTP/1.1\r\n";
  const auto r = decode(as_bytes(http));  // shorter than a header, but clearly not a frame
  EXPECT_EQ(r.error, DecodeError::BadMagic);
  EXPECT_EQ(decode(as_bytes("MT")).error, DecodeError::Truncated);
  EXPECT_EQ(decode(as_bytes("MX")).error, DecodeError::BadMagic);
  EXPECT_EQ(decode(as_bytes("MTRL\x07")).error, DecodeError::BadVersion);
}

TEST(WireDecode, BadVersion) {
  const auto r = decode(raw_frame(3, valid_delta_payload(), 1, 1));  // a version-1 peer
  EXPECT_EQ(r.error, DecodeError::BadVersion);
  EXPECT_NE(r.detail.find("version 1"), std::string::npos) << r.detail;
}

TEST(WireDecode, OversizedLengthIsRejectedFromTheHeaderAlone) {
  std::vector<std::uint8_t> f = raw_frame(4, {});
  const std::uint32_t len = kMaxPayloadSize + 1;
  for (int i = 0; i < 4; ++i) f[8 + i] = static_cast<std::uint8_t>(len >> (8 * i));
  const auto r = decode(f);  // only the header is present: the limit is checked before waiting
  EXPECT_EQ(r.error, DecodeError::Oversized);
  EXPECT_EQ(peek_header(f).error, DecodeError::Oversized);
}

TEST(WireDecode, MaximumPayloadIsAccepted) {
  // A HEARTBEAT must be empty, so use the limit on an unknown type to test the size rule alone.
  const auto r = decode(raw_frame(99, std::vector<std::uint8_t>(kMaxPayloadSize, 0)));
  EXPECT_EQ(r.error, DecodeError::UnknownType);
  EXPECT_EQ(r.frame_size, kMaxFrameSize);
}

TEST(WireDecode, EverySingleBitFlipIsDetected) {
  const auto good = encode(Frame{9, 10, Delta{{{sig::kSpeed, SignalStatus::Valid, 42.0, true, "hi"}}}});
  for (std::size_t byte = 0; byte < good.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      auto bad = good;
      bad[byte] ^= static_cast<std::uint8_t>(1U << bit);
      const auto r = decode(bad);
      EXPECT_NE(r.error, DecodeError::None) << "byte " << byte << " bit " << bit;
    }
  }
}

TEST(WireDecode, BadCrc) {
  auto f = raw_frame(3, valid_delta_payload());
  f.back() ^= 0x01;
  const auto r = decode(f);
  EXPECT_EQ(r.error, DecodeError::BadCrc);
  EXPECT_NE(r.detail.find("CRC"), std::string::npos);
}

TEST(WireDecode, UnknownType) {
  for (std::uint8_t type : {0, 8, 200}) {
    const auto r = decode(raw_frame(type, {1, 2, 3}));
    EXPECT_EQ(r.error, DecodeError::UnknownType) << int(type);
    EXPECT_EQ(r.frame_size, kHeaderSize + 3);
  }
}

struct MalformedCase {
  const char* name;
  std::uint8_t type;
  std::vector<std::uint8_t> payload;
  std::uint16_t header_flags = 0;
};

std::vector<MalformedCase> malformed_cases() {
  std::vector<MalformedCase> cases;
  auto delta = [](auto&& fill) {
    std::vector<std::uint8_t> p = {0, 0};
    put_le(p, 1, 2);
    fill(p);
    return p;
  };
  cases.push_back({"reserved header flags", 3, valid_delta_payload(), 0x0002});
  cases.push_back({"unknown signal id", 3, delta([](auto& p) { put_entry(p, 999, 0, 1.0); })});
  cases.push_back({"status out of range", 3, delta([](auto& p) { put_entry(p, 1, 4, 1.0); })});
  cases.push_back({"NaN value", 3, delta([](auto& p) { put_entry(p, 1, 0, std::nan("")); })});
  cases.push_back({"infinite value", 3, delta([](auto& p) { put_entry(p, 1, 0, -INFINITY); })});
  cases.push_back({"reserved entry flags", 3, delta([](auto& p) { put_entry(p, 1, 0, 1.0, 0x02); })});
  cases.push_back({"text runs past end", 3, delta([](auto& p) {
                     put_entry(p, 1, 0, 1.0, 0x01);
                     p.push_back(10);
                     p.push_back('a');
                   })});
  cases.push_back({"invalid UTF-8 text", 3, delta([](auto& p) {
                     put_entry(p, 1, 0, 1.0, 0x01);
                     p.push_back(2);
                     p.push_back(0xC0);
                     p.push_back(0x80);  // overlong NUL
                   })});
  cases.push_back({"count larger than entries", 3, [] {
                     std::vector<std::uint8_t> p = {0, 0};
                     put_le(p, 2, 2);
                     put_entry(p, 1, 0, 1.0);
                     return p;
                   }()});
  cases.push_back({"huge count", 2, {1, 0, 0xFF, 0xFF}});
  cases.push_back({"trailing bytes", 3, [] {
                     auto p = valid_delta_payload();
                     p.push_back(0);
                     return p;
                   }()});
  cases.push_back({"DELTA with flags", 3, [] {
                     auto p = valid_delta_payload();
                     p[0] = 1;
                     return p;
                   }()});
  cases.push_back({"SNAPSHOT reserved flag bits", 2, {0x81, 0, 0, 0}});
  cases.push_back({"list reserved byte", 2, {1, 7, 0, 0}});
  cases.push_back({"short list header", 3, {0, 0}});
  cases.push_back({"HEARTBEAT with payload", 4, {0}});
  cases.push_back({"STATUS too short", 5, std::vector<std::uint8_t>(19, 0)});
  cases.push_back({"STATUS too long", 5, std::vector<std::uint8_t>(21, 0)});
  cases.push_back({"CLOSE unknown reason", 6, {8, 0}});
  cases.push_back({"CLOSE text past end", 6, {1, 5, 'a'}});
  cases.push_back({"CLOSE empty", 6, {}});
  auto hello = [](std::uint8_t role, std::uint8_t flags, std::uint8_t name_len, std::string name,
                  std::optional<std::string> source = std::string()) {
    std::vector<std::uint8_t> p = {role, flags};
    put_le(p, 2, 2);
    put_le(p, 0, 8);
    put_le(p, 0, 2);
    put_le(p, 100, 4);
    p.push_back(name_len);
    p.insert(p.end(), name.begin(), name.end());
    if (source) {
      p.push_back(static_cast<std::uint8_t>(source->size()));
      p.insert(p.end(), source->begin(), source->end());
    }
    return p;
  };
  cases.push_back({"HELLO role 0", 1, hello(0, 0, 0, "")});
  cases.push_back({"HELLO role 3", 1, hello(3, 0, 0, "")});
  cases.push_back({"HELLO reserved flag bits", 1, hello(2, 2, 0, "")});
  cases.push_back({"HELLO name past end", 1, hello(1, 0, 5, "ab")});
  cases.push_back({"HELLO name too long", 1, hello(1, 0, 65, std::string(65, 'a'))});
  cases.push_back({"HELLO short", 1, {1, 0, 1}});
  cases.push_back({"HELLO without catalog source", 1, hello(1, 0, 1, "c", std::nullopt)});
  cases.push_back({"HELLO catalog source not UTF-8", 1, hello(1, 0, 1, "c", std::string("\xC3"))});
  cases.push_back({"HELLO without key id (version 2's layout)", 1, hello(1, 0, 1, "c", std::string("x"))});
  auto short_nonce = hello(1, 0, 1, "c", std::string("x"));
  put_le(short_nonce, 7, 4);
  short_nonce.resize(short_nonce.size() + kNonceSize - 1);
  cases.push_back({"HELLO nonce short", 1, short_nonce});
  auto piece = [](std::uint16_t index, std::uint16_t count, std::uint32_t len, std::string bytes) {
    std::vector<std::uint8_t> p;
    put_le(p, 7, 8);
    put_le(p, index, 2);
    put_le(p, count, 2);
    put_le(p, len, 4);
    p.insert(p.end(), bytes.begin(), bytes.end());
    return p;
  };
  cases.push_back({"CATALOG short", 7, std::vector<std::uint8_t>(15, 0)});
  cases.push_back({"CATALOG count 0", 7, piece(0, 0, 1, "{")});
  cases.push_back({"CATALOG index past count", 7, piece(2, 2, 1, "{")});
  cases.push_back({"CATALOG length past end", 7, piece(0, 1, 5, "{")});
  cases.push_back({"CATALOG length short of end", 7, piece(0, 1, 1, "{}")});
  return cases;
}

TEST(WireDecode, EveryMalformedPayloadIsRejectedWithADetail) {
  for (const auto& c : malformed_cases()) {
    const auto r = decode(raw_frame(c.type, c.payload, 1, kProtocolVersion, c.header_flags));
    EXPECT_EQ(r.error, DecodeError::Malformed) << c.name << ": " << to_string(r.error) << " " << r.detail;
    EXPECT_FALSE(r.detail.empty()) << c.name;
  }
}

TEST(WireDecode, BytesAfterTheFrameAreLeftToTheCaller) {
  auto f = encode(Frame{1, 2, Heartbeat{}});
  const std::size_t size = f.size();
  f.push_back(0xEE);
  const auto r = decode(f);
  EXPECT_EQ(r.error, DecodeError::None);
  EXPECT_EQ(r.frame_size, size);
}

TEST(Utf8, AcceptsValidRejectsInvalid) {
  EXPECT_TRUE(is_valid_utf8("plain"));
  EXPECT_TRUE(is_valid_utf8("\xE2\x82\xAC"));          // €
  EXPECT_TRUE(is_valid_utf8("\xF0\x9F\x9A\x97"));      // 🚗
  EXPECT_FALSE(is_valid_utf8("\xE2\x82"));              // cut
  EXPECT_FALSE(is_valid_utf8("\xED\xA0\x80"));          // surrogate
  EXPECT_FALSE(is_valid_utf8("\xF4\x90\x80\x80"));      // > U+10FFFF
  EXPECT_FALSE(is_valid_utf8("\xE0\x80\xAF"));          // overlong
  EXPECT_FALSE(is_valid_utf8("\x80"));
}

}  // namespace
}  // namespace meter::protocol
