#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"

using namespace meter::controller;

namespace {
const char* kQuirky =
    "VERSION \"quirks\"\r\n"
    "NS_ :\r\n\tCM_\r\n\tBA_\r\n\r\nBS_:\r\nBU_: ECU1 ECU2\r\n"
    "// a line comment\r\n"
    "BO_ 100 Msg1: 8 ECU1\r\n"
    " SG_ Speed: 0|16@1+ (0.01, 0) [0|300] \"km/h\" ECU2,ECU1\r\n"
    " SG_ Temp : 23|12@0- (-0.5,10) [-1000|1000] \"\xB0" "C\" ECU2\r\n"
    " SG_ Mux M : 63|8@0+ (1,0) [0|0] \"\" ECU2\r\n"
    "BO_ 2147484648 Ext: 8 ECU1\r\n"
    " SG_ Big : 0|64@1- (1,0) [0|0] \"\" ECU2\r\n"
    "BO_ 300 Muxed: 8 ECU1\r\n"
    " SG_ Sel M : 0|8@1+ (1,0) [0|0] \"\" ECU2\r\n"
    " SG_ A m1 : 8|16@1+ (1,0) [0|0] \"\" ECU2\r\n"
    " SG_ B m2 : 8|16@1- (1,0) [0|0] \"\" ECU2\r\n"
    " SG_ F : 32|32@1- (1,0) [0|0] \"\" ECU2\r\n"
    "CM_ SG_ 100 Speed \"vehicle speed,\r\n two lines\";\r\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\r\n"
    "BA_DEF_DEF_ \"GenMsgCycleTime\" 0;\r\n"
    "BA_ \"GenMsgCycleTime\" BO_ 100 20;\r\n"
    "VAL_ 300 Sel 1 \"one\" 2 \"two\" ;\r\n"
    "SIG_VALTYPE_ 300 F : 1;\r\n";
}  // namespace

TEST(Dbc, ParsesQuirksAndCp1252) {
  Database db = parse_dbc(kQuirky, "quirks.dbc");
  ASSERT_EQ(db.messages.size(), 3u);
  const DbcMessage* m = db.find(100, false);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->cycle_time_ms.value_or(-1), 20);
  ASSERT_EQ(m->signals.size(), 3u);
  EXPECT_EQ(m->signals[0].receivers.size(), 2u);
  EXPECT_EQ(m->signals[0].comment, "vehicle speed,\n two lines");
  EXPECT_EQ(m->signals[1].unit, "\xC2\xB0" "C");  // cp1252 degree sign became UTF-8
  EXPECT_FALSE(m->signals[1].little_endian);
  EXPECT_DOUBLE_EQ(m->signals[1].factor, -0.5);
  const DbcMessage* e = db.find(1000, true);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->name, "Ext");
  EXPECT_EQ(db.find(1000, false), nullptr);
  const DbcMessage* x = db.find("Muxed");
  ASSERT_NE(x, nullptr);
  EXPECT_EQ(x->signals[3].value_type, ValueType::Float32);
  EXPECT_EQ(x->signals[1].mux_switch, 0);
  EXPECT_EQ(*x->signals[0].choice(2), "two");
}

TEST(Dbc, MultiplexedSignalsFollowTheSwitch) {
  Database db = parse_dbc(kQuirky, "quirks.dbc");
  const DbcMessage& m = *db.find("Muxed");
  std::vector<DecodedSignal> out;
  std::uint8_t p1[8] = {1, 0x34, 0x12, 0, 0, 0, 0x80, 0x3F};
  decode(m, p1, out);
  ASSERT_EQ(out.size(), 3u);  // Sel, A, F
  EXPECT_EQ(m.signals[static_cast<std::size_t>(out[1].signal)].name, "A");
  EXPECT_EQ(out[1].physical, 0x1234);
  EXPECT_EQ(out[2].physical, 1.0);  // float32 1.0f
  std::uint8_t p2[8] = {2, 0xFE, 0xFF, 0, 0, 0, 0xC0, 0x7F};  // B = -2, F = NaN
  decode(m, p2, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(m.signals[static_cast<std::size_t>(out[1].signal)].name, "B");
  EXPECT_EQ(out[1].physical, -2);
  EXPECT_EQ(out[2].status, DecodeStatus::NotFinite);
  EXPECT_EQ(out[2].physical, 0.0);
  std::uint8_t p3[8] = {7, 0, 0, 0, 0, 0, 0, 0};
  decode(m, p3, out);
  EXPECT_EQ(out.size(), 2u);  // neither A nor B
}

TEST(Dbc, ShortFrameAndRangeFlags) {
  Database db = parse_dbc(kQuirky, "quirks.dbc");
  const DbcMessage& m = *db.find("Msg1");
  std::vector<DecodedSignal> out;
  std::uint8_t p[2] = {0x10, 0x27};  // Speed = 100.00, Temp and Mux missing
  decode(m, p, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].status, DecodeStatus::Valid);
  EXPECT_DOUBLE_EQ(out[0].physical, 100.0);
  EXPECT_EQ(out[1].status, DecodeStatus::ShortFrame);
  EXPECT_EQ(out[2].status, DecodeStatus::ShortFrame);
  std::uint8_t q[8] = {0x50, 0xC3, 0, 0, 0, 0, 0, 0};  // 500.00 km/h > 300
  decode(m, q, out);
  EXPECT_EQ(out[0].status, DecodeStatus::OutOfRange);
}

// physical = raw * factor + offset as the DBC writes it: the product rounded to a double, then the
// sum, on every processor. A compiler may fuse the two into one multiply-add with a single rounding
// (GCC does on arm64 unless told not to), which moves the last bits: the real ft86 drive's BOOST,
// raw 45 with (1.9885, -98.85), decoded -9.3675 on arm64 and -9.367499999999993 on x86-64 and in
// canmatrix.
TEST(Dbc, PhysicalValueRoundsTheProductThenTheSum) {
  Database db = parse_dbc("BO_ 864 ID_360: 8 X\n SG_ BOOST : 32|8@1+ (1.9885,-98.85) [-99|507] \"kPa\" X\n", "boost.dbc");
  std::vector<DecodedSignal> out;
  std::uint8_t p[8] = {0, 0, 0, 0, 45, 0, 0, 0};
  decode(db.messages[0], p, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].raw, 45u);
  EXPECT_EQ(out[0].physical, -9.367499999999993);  // (45 * 1.9885 = 89.4825, rounded) - 98.85, rounded
  EXPECT_EQ(raw_to_physical(db.messages[0].signals[0], 45), -9.367499999999993);
}

// A signal whose bytes are missing is decoded from zero padding; with a huge factor that product
// can overflow, and the padded value must not leak out as inf beside its ShortFrame status (found by
// the dbc fuzz target).
TEST(Dbc, FuzzShortFrameOfAHugeFactorSignalStaysFinite) {
  Database db = parse_dbc("BO_ 1 M: 8 X\n SG_ Big : 0|64@1+ (1e300,0) [0|0] \"\" X\n", "huge.dbc");
  std::vector<DecodedSignal> out;
  std::uint8_t p[4] = {0xFF, 0xFF, 0xFF, 0xFF};  // 4 of the 8 bytes: the raw is 2^32 - 1, physical 4.3e309
  decode(db.messages[0], p, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].status, DecodeStatus::ShortFrame);
  EXPECT_TRUE(std::isfinite(out[0].physical)) << out[0].physical;
}

TEST(Dbc, EncodeDecodeRoundTripRandomLayouts) {
  // Every layout (order, sign, start, length) round-trips raw bits, and neighbours stay untouched.
  std::mt19937_64 rng(42);
  for (int iter = 0; iter < 20000; ++iter) {
    DbcSignal s;
    s.name = "S";
    s.little_endian = rng() & 1;
    s.is_signed = rng() & 1;
    s.length = static_cast<std::uint16_t>(1 + rng() % 64);
    std::uint8_t payload[8];
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    std::uint8_t before[8];
    std::memcpy(before, payload, 8);
    // Pick a start bit that keeps the signal inside 8 bytes.
    for (;;) {
      s.start_bit = static_cast<std::uint16_t>(rng() % 64);
      if (s.bytes_needed() <= 8 && (s.little_endian ? s.start_bit + s.length <= 64 : true)) break;
    }
    std::uint64_t raw = rng();
    if (s.length < 64) raw &= (1ull << s.length) - 1;
    insert_raw(s, raw, payload);
    std::uint64_t got = extract_raw(s, payload);
    std::uint64_t expect = raw;
    if (s.is_signed && s.length < 64 && (raw >> (s.length - 1)) & 1) expect |= ~((1ull << s.length) - 1);
    ASSERT_EQ(got, expect) << "len " << s.length << " start " << s.start_bit << " le " << s.little_endian;
    // Clearing the signal restores every bit outside it.
    int changed = 0;
    insert_raw(s, 0, payload);
    for (int i = 0; i < 64; ++i) {
      bool now = (payload[i / 8] >> (i % 8)) & 1, was = (before[i / 8] >> (i % 8)) & 1;
      if (now != was && was) ++changed;
    }
    ASSERT_LE(changed, s.length);
  }
}

TEST(Dbc, PhysicalEncodeRoundsAndRejects) {
  DbcSignal s;
  s.name = "T";
  s.length = 12;
  s.is_signed = false;
  s.factor = -0.01;
  s.offset = 4100;  // negative scaling with a large offset, as in the cantools test DBCs
  EXPECT_EQ(physical_to_raw(s, 4100.0), 0u);
  EXPECT_EQ(physical_to_raw(s, 4070.0), 3000u);
  EXPECT_THROW(physical_to_raw(s, 5000.0), std::out_of_range);
  EXPECT_THROW(physical_to_raw(s, std::nan("")), std::invalid_argument);
  s.is_signed = true;
  s.factor = 1;
  s.offset = 0;
  EXPECT_EQ(physical_to_raw(s, -1), 0xFFFu);
  EXPECT_THROW(physical_to_raw(s, 2048), std::out_of_range);
}

TEST(Dbc, ProblemsNameFileLineAndExpectation) {
  // Lenient: the statement is skipped with a warning naming its line and what was expected;
  // --strict: the same text is a DbcError naming file:line.
  auto expect_problem = [](const std::string& text, int line, const std::string& what) {
    Database db = parse_dbc(text, "bad.dbc");
    bool found = false;
    for (const auto& w : db.warnings) found |= w.line == line && w.text.find(what) != std::string::npos;
    EXPECT_TRUE(found) << "no warning at line " << line << " about '" << what << "' for: " << text;
    try {
      parse_dbc(text, "bad.dbc", DbcOptions{true});
      ADD_FAILURE() << "--strict accepted: " << text;
    } catch (const DbcError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.dbc:" + std::to_string(line) + ":"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|8@2+ (1,0) [0|0] \"\" X\n", 2, "byte order");
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|8@1+ (1 0) [0|0] \"\" X\n", 2, "expected ','");
  expect_problem("\n\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\n", 3, "before any BO_");
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|0@1+ (1,0) [0|0] \"\" X\n", 2, "1..64");
  expect_problem("BO_ 1 M: 8 X\n SG_ S m1 : 0|8@1+ (1,0) [0|0] \"\" X\n", 2, "no multiplexor");
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\nSIG_VALTYPE_ 1 S : 1;\n", 3, "32-bit");
  expect_problem("BO_ 1 M: 8 X\nCM_ BO_ 1 \"never closed;\n", 2, "unterminated string");
  expect_problem("BO_ x M: 8 X\n", 1, "message id");
  expect_problem("BA_DEF_ BO_ \"X\" INT 0 1\n", 1, "has no ';'");
  // A number past the largest double (found by the dbc fuzz target as a factor of 0.39e308686...)
  // would scale every value to inf or NaN.
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|8@1+ (0.39e308686, 0) [0|0] \"\" X\n", 2, "too large for a double");
  expect_problem("BO_ 1 M: 8 X\n SG_ S : 0|8@1+ (1, -2e308) [0|0] \"\" X\n", 2, "too large for a double");
  EXPECT_THROW(load_dbc("/nonexistent/file.dbc"), DbcError);
}

TEST(Dbc, EveryBundledDbcParses) {
  for (const char* f : {"CSS-Electronics-SAE-J1939-DEMO.dbc", "cantools_choices.dbc", "cantools_fd_test.dbc",
                        "cantools_floating_point.dbc", "cantools_issue_636_negative_scaling.dbc", "cantools_j1939.dbc",
                        "cantools_motohawk.dbc", "cantools_multiplex.dbc", "cantools_signed.dbc",
                        "cantools_vehicle.dbc"}) {
    SCOPED_TRACE(f);
    // A path, not a chain of std::string +: GCC 12 at -O1 warns of a memcpy out of bounds in that chain
    // once a unity batch inlines it (a false -Warray-bounds, fixed in GCC 13).
    Database db = load_dbc((std::filesystem::path(METER_SHARED_DIR) / "data/can/dbc_semantics" / f).string());
    EXPECT_FALSE(db.messages.empty());
  }
  Database v = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/dbc_semantics/cantools_vehicle.dbc");
  EXPECT_GT(v.messages.size(), 100u);
  Database mux = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/dbc_semantics/cantools_multiplex.dbc");
  const DbcMessage* m = mux.find("Message1");
  ASSERT_NE(m, nullptr);
  EXPECT_TRUE(m->extended);
  EXPECT_EQ(m->id, 0x0123456u);
  // SG_MUL_VAL_ widened BIT_L to switch values 8, 16 and 24.
  const DbcSignal& l = m->signals[static_cast<std::size_t>(m->find_signal("BIT_L"))];
  EXPECT_EQ(l.mux_ranges.size(), 3u);
  // cantools_choices.dbc is cp1252: its value table text arrives as UTF-8, negative keys work.
  Database ch = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/dbc_semantics/cantools_choices.dbc");
  const DbcSignal& foo = ch.find("Foo")->signals[0];
  ASSERT_NE(foo.choice(1), nullptr);
  EXPECT_EQ(*foo.choice(1), "#%=*\xC3\xA4'");
  std::uint8_t neg[8] = {0xFB, 0, 0, 0, 0, 0, 0, 0};
  std::vector<DecodedSignal> dec;
  decode(*ch.find("Foo"), neg, dec);
  ASSERT_EQ(dec.size(), 1u);
  EXPECT_EQ(*foo.choice(dec[0].raw_signed()), "A negative value");
  Database fd = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/dbc_semantics/cantools_fd_test.dbc");
  // VFrameFormat enum index 14/15 = StandardCAN_FD / ExtendedCAN_FD.
  EXPECT_TRUE(fd.find("TestMsg_FDStd")->fd);
  EXPECT_TRUE(fd.find("TestMsg_FDEx")->fd);
  EXPECT_FALSE(fd.find("TestMsg_Ex")->fd);
  EXPECT_TRUE(fd.find("TestMsg_Ex")->extended);
}

TEST(Dbc, MutatedFilesNeverCrash) {
  // Truncations and byte flips of real files (one with extended multiplexing, one with quirks:
  // missing ';', comments naming no signal): the lenient parse always gives a database (broken
  // statements become warnings), --strict a database or a DbcError; nothing else (run under
  // ASan/UBSan in CI).
  std::vector<std::string> bases;
  for (const char* f : {"/data/can/dbc_semantics/cantools_multiplex.dbc", "/data/can/opendbc/chrysler_pacifica_2017_hybrid_generated.dbc"}) {
    std::ifstream in(std::string(METER_SHARED_DIR) + f, std::ios::binary);
    bases.emplace_back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(bases.back().empty()) << f;
  }
  std::mt19937 rng(99);
  int errors = 0, parsed = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string t = bases[static_cast<std::size_t>(i) % bases.size()];
    if (i % 3 == 0) t.resize(1 + rng() % (t.size() - 1));
    for (int k = 0; k < 1 + static_cast<int>(rng() % 4); ++k) t[rng() % t.size()] = static_cast<char>(rng());
    Database db = parse_dbc(t, "fuzz.dbc");
    for (const auto& m : db.messages) {
      std::vector<DecodedSignal> out;
      std::uint8_t p[64];
      for (auto& b : p) b = static_cast<std::uint8_t>(rng());
      decode(m, std::span(p, rng() % 65), out);
    }
    try {
      Database strict = parse_dbc(t, "fuzz.dbc", DbcOptions{true});
      EXPECT_TRUE(db.warnings.empty());  // strict accepts exactly what gives no warning
      EXPECT_EQ(strict.messages.size(), db.messages.size());
      ++parsed;
    } catch (const DbcError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.dbc:"), std::string::npos);
      ++errors;
    }
  }
  EXPECT_GT(errors, 0);
  EXPECT_GT(parsed, 0);
}
