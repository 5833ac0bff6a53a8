// DBC decoding and encoding at the numeric edges (docs/numerics.md, "Decoding").
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"

using namespace meter::controller;

namespace {

DbcSignal sig(unsigned len, bool is_signed, bool intel = true, ValueType vt = ValueType::Integer, double factor = 1, double offset = 0) {
  DbcSignal s;
  s.name = "S";
  s.start_bit = intel ? 0 : 7;  // Motorola: MSB of byte 0
  s.length = static_cast<std::uint16_t>(len);
  s.little_endian = intel;
  s.is_signed = is_signed;
  s.value_type = vt;
  s.factor = factor;
  s.offset = offset;
  return s;
}

// Decodes one 8-byte frame whose payload carries `raw` for signal s.
DecodedSignal decode_one(const DbcSignal& s, std::uint64_t raw) {
  DbcMessage m;
  m.name = "M";
  m.size = 8;
  m.signals = {s};
  std::uint8_t p[8] = {};
  insert_raw(s, raw, p);
  std::vector<DecodedSignal> out;
  EXPECT_EQ(decode(m, p, out), 1u);
  return out.at(0);
}

constexpr double kTwo63 = 9223372036854775808.0;

}  // namespace

// 64-bit signed extremes, both byte orders: INT64_MIN exact, -1 exact, INT64_MAX within 1 of the
// true value (the nearest double is 2^63: 0.5 ulp), and the raw round-trips bit-exactly.
TEST(Decode, SixtyFourBitSignedExtremes) {
  for (bool intel : {true, false}) {
    const auto s = sig(64, true, intel);
    auto d = decode_one(s, 0x8000000000000000ull);
    EXPECT_EQ(d.raw_signed(), std::numeric_limits<std::int64_t>::min());
    EXPECT_EQ(d.physical, -kTwo63);
    EXPECT_EQ(d.status, DecodeStatus::Valid);
    d = decode_one(s, 0x7FFFFFFFFFFFFFFFull);
    EXPECT_EQ(d.raw_signed(), std::numeric_limits<std::int64_t>::max());
    EXPECT_EQ(d.physical, kTwo63);  // 2^63 - 1 rounds to 2^63: error 1 in 9.2e18
    EXPECT_EQ(decode_one(s, ~0ull).physical, -1.0);
    // Encoding the extremes: -2^63 fits, +2^63 (the double closest to INT64_MAX) does not.
    EXPECT_EQ(physical_to_raw(s, -kTwo63), 0x8000000000000000ull);
    EXPECT_THROW(physical_to_raw(s, kTwo63), std::out_of_range);
    EXPECT_EQ(physical_to_raw(s, -1.0), ~0ull);
  }
  // Unsigned 64-bit: all ones decodes to 2^64 (nearest double); 2^64 does not encode.
  const auto u = sig(64, false);
  EXPECT_EQ(decode_one(u, ~0ull).physical, 18446744073709551616.0);
  EXPECT_THROW(physical_to_raw(u, 18446744073709551616.0), std::out_of_range);
  EXPECT_EQ(physical_to_raw(u, 9007199254740992.0), 9007199254740992ull);  // 2^53 exact
  // Signed widths 1..63: the most negative raw sign-extends exactly.
  for (unsigned len = 1; len < 64; ++len) {
    const auto s = sig(len, true);
    EXPECT_EQ(decode_one(s, 1ull << (len - 1)).physical, -std::ldexp(1.0, static_cast<int>(len) - 1)) << len;
    EXPECT_THROW(physical_to_raw(s, std::ldexp(1.0, static_cast<int>(len) - 1)), std::out_of_range) << len;
  }
}

// Tiny, huge, negative and zero factors: results are the IEEE product (relative 1 ulp), a product
// that overflows is NotFinite with physical 0 (never Inf on the wire), encoding never hits UB.
TEST(Decode, TinyHugeNegativeAndZeroFactors) {
  auto d = decode_one(sig(16, false, true, ValueType::Integer, 1e-300), 40000);
  EXPECT_DOUBLE_EQ(d.physical, 4e-296);
  d = decode_one(sig(16, false, true, ValueType::Integer, 4.9406564584124654e-324), 3);  // subnormal factor
  EXPECT_EQ(d.physical, 3 * 4.9406564584124654e-324);
  EXPECT_EQ(d.status, DecodeStatus::Valid);
  d = decode_one(sig(64, false, true, ValueType::Integer, 1e300), ~0ull);
  EXPECT_EQ(d.status, DecodeStatus::NotFinite);
  EXPECT_EQ(d.physical, 0.0);
  d = decode_one(sig(64, true, true, ValueType::Integer, -1e300), 0x8000000000000000ull);
  EXPECT_EQ(d.status, DecodeStatus::NotFinite);
  // Negative factor with offset (cantools #636 shape) and range check.
  auto neg = sig(12, false, true, ValueType::Integer, -0.01, 4100);
  neg.minimum = 4060, neg.maximum = 4100;
  d = decode_one(neg, 3000);
  EXPECT_NEAR(d.physical, 4070.0, 1e-9);
  EXPECT_EQ(d.status, DecodeStatus::Valid);
  EXPECT_EQ(decode_one(neg, 4095).status, DecodeStatus::OutOfRange);  // 4059.05
  EXPECT_EQ(physical_to_raw(neg, 4070.0), 3000u);
  // Zero factor: every raw decodes to the offset; encoding anything is refused (it used to divide
  // 0/0 and convert NaN to an integer: undefined behaviour).
  const auto zero = sig(8, false, true, ValueType::Integer, 0.0, 5.0);
  EXPECT_EQ(decode_one(zero, 200).physical, 5.0);
  EXPECT_THROW(physical_to_raw(zero, 5.0), std::out_of_range);
  EXPECT_THROW(physical_to_raw(zero, 6.0), std::out_of_range);
  // Tiny factor: a modest value needs a raw far outside 64 bits: refused, not wrapped.
  EXPECT_THROW(physical_to_raw(sig(64, true, true, ValueType::Integer, 1e-300), 1.0), std::out_of_range);
}

// IEEE float/double signals carrying NaN, +-Inf and subnormals: NaN/Inf are NotFinite with
// physical 0; subnormals decode exactly (bit-exact round trip through encode).
TEST(Decode, FloatAndDoubleNanInfSubnormal) {
  const auto f = sig(32, false, true, ValueType::Float32);
  const auto dd = sig(64, false, true, ValueType::Float64);
  for (std::uint32_t bits : {0x7FC00000u, 0x7FA00001u, 0xFFC00000u, 0x7F800000u, 0xFF800000u}) {
    auto d = decode_one(f, bits);
    EXPECT_EQ(d.status, DecodeStatus::NotFinite) << std::hex << bits;
    EXPECT_EQ(d.physical, 0.0);
  }
  for (std::uint64_t bits : {0x7FF8000000000000ull, 0x7FF0000000000001ull, 0x7FF0000000000000ull, 0xFFF0000000000000ull}) {
    auto d = decode_one(dd, bits);
    EXPECT_EQ(d.status, DecodeStatus::NotFinite) << std::hex << bits;
    EXPECT_EQ(d.physical, 0.0);
  }
  const float fsub = std::numeric_limits<float>::denorm_min();
  auto d = decode_one(f, std::bit_cast<std::uint32_t>(fsub));
  EXPECT_EQ(d.status, DecodeStatus::Valid);
  EXPECT_EQ(d.physical, static_cast<double>(fsub));
  EXPECT_EQ(physical_to_raw(f, d.physical), std::bit_cast<std::uint32_t>(fsub));
  const double dsub = std::numeric_limits<double>::denorm_min();
  d = decode_one(dd, std::bit_cast<std::uint64_t>(dsub));
  EXPECT_EQ(d.status, DecodeStatus::Valid);
  EXPECT_EQ(d.physical, dsub);
  EXPECT_EQ(physical_to_raw(dd, dsub), std::bit_cast<std::uint64_t>(dsub));
  // -0.0 stays a number; float max decodes exactly; a value beyond float range is refused on encode.
  EXPECT_EQ(decode_one(f, 0x80000000u).status, DecodeStatus::Valid);
  EXPECT_EQ(decode_one(f, std::bit_cast<std::uint32_t>(std::numeric_limits<float>::max())).physical,
            static_cast<double>(std::numeric_limits<float>::max()));
  EXPECT_THROW(physical_to_raw(f, 1e39), std::out_of_range);
  // Double max times a factor of 10 overflows: NotFinite, not Inf.
  const auto big = sig(64, false, true, ValueType::Float64, 10.0);
  EXPECT_EQ(decode_one(big, std::bit_cast<std::uint64_t>(std::numeric_limits<double>::max())).status, DecodeStatus::NotFinite);
  EXPECT_THROW(physical_to_raw(f, std::nan("")), std::invalid_argument);
  EXPECT_THROW(physical_to_raw(dd, -INFINITY), std::invalid_argument);
}
