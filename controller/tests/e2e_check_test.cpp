// The E2E stage's logic: the counter state machine, a message's configuration resolved against
// its DBC (where the checksum must sit), the per-frame check, detection from the DBC's
// conventions, the map file's [e2e] sections, and the model refusing a failing frame so its
// signals age and time out.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "../src/run/health_report.hpp"
#include "meter/controller/dbc/parse.hpp"
#include "meter/controller/e2e/autosar_profile01.hpp"
#include "meter/controller/e2e/e2e_detect.hpp"
#include "meter/controller/e2e/e2e_guard.hpp"
#include "meter/controller/e2e/toyota_checksum.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "model_fixture.hpp"

namespace meter::controller {
namespace {

using testing::frame;
using testing::ms;

TEST(E2eCounter, CountsRepeatedAndSkippedApart) {
  CounterState st;
  const CounterTolerance tol{2, 0, 1};
  EXPECT_EQ(check_counter(st, 14, 16, tol).status, CounterStatus::Initial);
  EXPECT_EQ(check_counter(st, 15, 16, tol).status, CounterStatus::Ok);
  EXPECT_EQ(check_counter(st, 0, 16, tol).status, CounterStatus::Ok);  // wraps
  EXPECT_EQ(check_counter(st, 0, 16, tol).status, CounterStatus::Repeated);
  const CounterResult skip = check_counter(st, 2, 16, tol);
  EXPECT_EQ(skip.status, CounterStatus::Skipped);
  EXPECT_EQ(skip.lost, 1u);
  EXPECT_EQ(check_counter(st, 9, 16, tol).status, CounterStatus::WrongSequence);
  EXPECT_EQ(check_counter(st, 10, 16, tol).status, CounterStatus::Ok);  // sync_frames 0: back at once
}

TEST(E2eCounter, ResynchronisesAfterAWrongSequenceAndTooManyRepeats) {
  CounterState st;
  const CounterTolerance tol{1, 2, 0};
  check_counter(st, 0, 16, tol);
  EXPECT_EQ(check_counter(st, 5, 16, tol).status, CounterStatus::WrongSequence);
  EXPECT_EQ(check_counter(st, 6, 16, tol).status, CounterStatus::Syncing);
  EXPECT_EQ(check_counter(st, 7, 16, tol).status, CounterStatus::Syncing);
  EXPECT_EQ(check_counter(st, 8, 16, tol).status, CounterStatus::Ok);
  EXPECT_EQ(check_counter(st, 8, 16, tol).status, CounterStatus::Repeated);  // max_repeated 0: resync
  EXPECT_EQ(check_counter(st, 9, 16, tol).status, CounterStatus::Syncing);
  EXPECT_EQ(check_counter(st, 11, 16, tol).status, CounterStatus::WrongSequence);  // max_delta 1: no loss tolerated
}

// A Toyota-style message: speed, a 4-bit counter in byte 5, the checksum in the last byte.
const char* kToyotaDbc =
    "BO_ 180 SPEED: 8 ECU\n"
    " SG_ SPEED : 7|16@0+ (0.01,0) [0|250] \"km/h\" ICL\n"
    " SG_ COUNTER : 40|4@1+ (1,0) [0|15] \"\" ICL\n"
    " SG_ CHECKSUM : 56|8@1+ (1,0) [0|255] \"\" ICL\n"
    "BO_ 181 PLAIN: 8 ECU\n"
    " SG_ X : 0|8@1+ (1,0) [0|255] \"\" ICL\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\nBA_ \"GenMsgCycleTime\" BO_ 180 10;\n";

CanFrame speed_frame(std::int64_t t, double kmh, unsigned counter, bool good = true) {
  const auto raw = static_cast<unsigned>(kmh * 100);
  CanFrame f = frame(180, t, {static_cast<std::uint8_t>(raw >> 8), static_cast<std::uint8_t>(raw), 0, 0, 0,
                              static_cast<std::uint8_t>(counter & 15), 0, 0});
  f.data[7] = static_cast<std::uint8_t>(toyota_checksum(180, std::span<const std::uint8_t>(f.data.data(), 8)) + (good ? 0 : 1));
  return f;
}

TEST(E2eMessage, ChecksAFrameAndSaysWhereTheChecksumMustSit) {
  const Database db = parse_dbc(kToyotaDbc, "toyota_test.dbc");
  E2eSpec spec;
  spec.message = "SPEED";
  spec.checksum = ChecksumKind::Toyota;
  const E2eMessage m = resolve_e2e(spec, *db.find("SPEED"));
  EXPECT_EQ(m.checksum_byte, 7u);
  EXPECT_EQ(m.counter_modulus, 16u);
  CounterState st;
  const CanFrame good = speed_frame(0, 50, 3), bad = speed_frame(0, 50, 4, false);
  EXPECT_TRUE(check_frame(m, st, 180, {good.data.data(), 8}).usable);
  const FrameCheck r = check_frame(m, st, 180, {bad.data.data(), 8});
  EXPECT_EQ(r.checksum, ChecksumStatus::Bad);
  EXPECT_FALSE(r.usable);
  EXPECT_EQ(check_frame(m, st, 180, {good.data.data(), 5}).checksum, ChecksumStatus::ShortFrame);
  // The bad frame did not move the counter on: counter 4 with a good checksum is still the next one.
  EXPECT_EQ(check_frame(m, st, 180, {speed_frame(0, 50, 4).data.data(), 8}).counter_result.status, CounterStatus::Ok);

  E2eSpec p01 = spec;  // profile 1's counter runs 0..14: a 15 is out of sequence whatever came before
  p01.checksum = ChecksumKind::Profile01;
  const E2eMessage m01 = resolve_e2e(p01, *db.find("SPEED"));
  CounterState st01;
  CanFrame f15 = speed_frame(0, 50, 15);
  f15.data[7] = autosar_profile01_crc({f15.data.data(), 8}, 7, 0, DataIdMode::Both, 15);
  const FrameCheck r15 = check_frame(m01, st01, 180, {f15.data.data(), 8});
  EXPECT_EQ(r15.checksum, ChecksumStatus::Ok);
  EXPECT_EQ(r15.counter_result.status, CounterStatus::WrongSequence);

  spec.checksum = ChecksumKind::Subaru;  // writes byte 0: this DBC puts the checksum in byte 7
  try {
    resolve_e2e(spec, *db.find("SPEED"));
    FAIL() << "resolved a checksum where the algorithm does not write it";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("byte 0, but signal CHECKSUM is 8 bits at start bit 56"), std::string::npos) << e.what();
  }
  spec.checksum = ChecksumKind::VwMqb;
  spec.checksum_signal = "NOPE";
  EXPECT_THROW(resolve_e2e(spec, *db.find("SPEED")), std::invalid_argument);
}

TEST(E2eDetect, ReadsTheMakeFromTheFileNameAndTheSignalsByName) {
  const Database db = parse_dbc(kToyotaDbc, "dbc/toyota_test.dbc");
  const E2eDetection d = detect_e2e(db);
  EXPECT_EQ(d.make, "Toyota");
  ASSERT_EQ(d.messages.size(), 1u);  // PLAIN carries neither
  EXPECT_EQ(d.messages[0].message, "SPEED");
  EXPECT_EQ(d.messages[0].checksum, ChecksumKind::Toyota);
  const E2eDetection unknown = detect_e2e(parse_dbc(kToyotaDbc, "mystery.dbc"));
  EXPECT_TRUE(unknown.make.empty());
  ASSERT_EQ(unknown.messages.size(), 1u);
  EXPECT_EQ(unknown.messages[0].checksum, ChecksumKind::None);  // a counter is still a counter
}

TEST(E2eDetect, ReadsTeslasSignalsNamedAfterTheirMessage) {
  const char* dbc =
      "BO_ 697 DAS_control: 8 DAS\n SG_ DAS_controlCounter : 53|3@1+ (1,0) [0|7] \"\" EPAS\n"
      " SG_ DAS_controlChecksum : 56|8@1+ (1,0) [0|255] \"\" EPAS\n"
      "BO_ 585 SCCM_leftStalk: 8 SCCM\n SG_ SCCM_leftStalkCounter : 8|4@1+ (1,0) [0|15] \"\" X\n";
  const E2eDetection d = detect_e2e(parse_dbc(dbc, "tesla_can.dbc"));
  ASSERT_EQ(d.messages.size(), 2u);
  EXPECT_EQ(d.messages[0].checksum, ChecksumKind::Tesla);
  EXPECT_EQ(d.messages[0].checksum_signal, "DAS_controlChecksum");
  EXPECT_EQ(d.messages[1].checksum, ChecksumKind::None);
  EXPECT_EQ(d.messages[1].counter_signal, "SCCM_leftStalkCounter");
  EXPECT_TRUE(detect_e2e(parse_dbc(dbc, "other.dbc")).messages.empty());  // the suffix rule is Tesla's alone
}

TEST(E2eDetect, FindsTheSubaruPreglobalMessagesOfOpendbc) {
  const Database db = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/opendbc/subaru_outback_2015_generated.dbc");
  const E2eDetection d = detect_e2e(db);
  EXPECT_EQ(d.checksum, ChecksumKind::SubaruPreglobal);
  int with_checksum = 0;
  for (const E2eSpec& s : d.messages) with_checksum += s.checksum == ChecksumKind::SubaruPreglobal;
  EXPECT_EQ(with_checksum, 5);  // Steering and the four ES_* messages
  EXPECT_EQ(d.messages.size(), 13u);
}

TEST(E2eMapFile, ParsesTheSectionsAndNamesEveryMistake) {
  const Mapping m = parse_mapping(
      "[e2e]\ndetect = true\nmismatch_ratio = 0.5\nmismatch_frames = 10\n"
      "[e2e SPEED]\nchecksum = autosar-p01\ndata_id = 0x123\ndata_id_mode = alternating\nmax_delta = 3\nsync_frames = 2\n"
      "[e2e body.PLAIN]\nchecksum = vw-mqb\ndata_ids = 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16\ncounter_signal = none\n",
      "e2e.map");
  EXPECT_TRUE(m.e2e.detect);
  EXPECT_EQ(m.e2e.mismatch_min_frames, 10u);
  ASSERT_EQ(m.e2e.messages.size(), 2u);
  EXPECT_EQ(m.e2e.messages[0].data_id, 0x123);
  EXPECT_EQ(m.e2e.messages[0].data_id_mode, DataIdMode::Alternating);
  EXPECT_EQ(m.e2e.messages[0].tolerance.max_delta, 3u);
  EXPECT_EQ(m.e2e.messages[1].message, "body.PLAIN");
  EXPECT_FALSE(m.e2e.messages[1].counter);
  EXPECT_EQ(m.e2e.messages[1].data_ids.size(), 16u);
  const std::pair<const char*, const char*> bad[] = {
      {"[e2e X]\nchecksum = crc32\n", "e2e.map:2: checksum: expected one of none, toyota"},
      {"[e2e X]\ndata_id = 70000\nchecksum = autosar-p05\n", "e2e.map:2: data_id: expected a whole number 0..65535"},
      {"[e2e X]\ndata_ids = 1 2 3\n", "e2e.map:2: data_ids: expected 16 values"},
      {"[e2e X]\nchecksum = autosar-p02\n", "e2e.map:1: [e2e X]: autosar-p02 needs data_ids"},
      {"[e2e X]\nchecksum = toyota\ndata_id = 5\n", "e2e.map:1: [e2e X]: data_id belongs to autosar-p01"},
      {"[e2e X]\nchecksum = autosar-p11\ndata_id_mode = low\n", "e2e.map:1: [e2e X]: autosar-p11 has data_id_mode both or nibble only"},
      {"[e2e X]\n[e2e X]\n", "e2e.map:2: section [e2e X] appears twice"},
      {"[e2e]\ndetect = maybe\n", "e2e.map:2: detect: expected true or false"},
      {"[e2e X]\nmax_delta = 0\n", "e2e.map:2: max_delta: expected a whole number 1..255"},
      {"[e2e X]\ncounter_signal = none\n", "e2e.map:1: [e2e X]: neither a checksum nor a counter"},
  };
  for (const auto& [text, want] : bad) {
    try {
      parse_mapping(text, "e2e.map");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const MappingError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  }
}

const char* kSpeedMap =
    "[Vehicle.Speed]\nsource = SPEED.SPEED\ntimeout = 100ms\n"
    "[e2e SPEED]\nchecksum = toyota\n";

TEST(E2eModel, AFailingFrameIsNotUsedAndItsSignalsTimeOut) {
  const Database db = parse_dbc(kToyotaDbc, "toyota_test.dbc");
  Model model(&db, parse_mapping(kSpeedMap, "speed.map"));
  model.start(0);
  std::int64_t t = 0;
  unsigned counter = 0;
  for (; t < 200 * ms; t += 10 * ms) {
    model.on_frame(speed_frame(t, 50, counter++));
    model.update(t);
  }
  const protocol::SignalId speed = protocol::find_signal("Vehicle.Speed")->id;
  EXPECT_EQ(model.output(speed)->status, protocol::SignalStatus::Valid);
  EXPECT_DOUBLE_EQ(model.output(speed)->value, 50);
  // A forger with the wrong checksum, then a replay of the last good frame: neither moves the
  // speed, and after the timeout it is shown invalid as for a silent sender.
  const CanFrame replay = speed_frame(0, 50, counter - 1);
  for (int i = 0; t < 400 * ms; t += 10 * ms, ++i) {
    CanFrame f = i % 2 ? speed_frame(t, 180, counter, false) : replay;
    f.timestamp_ns = t;
    model.on_frame(f);
    model.update(t);
    if (t < 290 * ms) {
      EXPECT_DOUBLE_EQ(model.output(speed)->value, 50);
    }
  }
  EXPECT_EQ(model.output(speed)->status, protocol::SignalStatus::TimedOut);
  EXPECT_EQ(model.stats().frames_refused, 20u);
  const auto& s = model.e2e().entries().at(0).stats;
  EXPECT_EQ(s.checksum_failed, 10u);
  EXPECT_EQ(s.repeated, 10u);
  EXPECT_TRUE(model.e2e().likely_mismatch(model.e2e().entries().at(0)) == false);  // 20 of 40 refused
  std::vector<E2eHealth> h;
  update_e2e_health(model.e2e(), h);
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(describe(h[0]), "SPEED 20 of 40 refused (10 checksum, 10 repeated, 0 out of sequence; 0 lost)");
  // The run loop's every tick: the same vector and names, only the counts rewritten.
  const E2eHealth* kept = h.data();
  const char* name = h[0].message.data();
  model.on_frame(speed_frame(t, 50, counter));
  update_e2e_health(model.e2e(), h);
  EXPECT_EQ(h.data(), kept);
  EXPECT_EQ(h[0].message.data(), name);
  EXPECT_EQ(h[0].checked, 41u);
}

TEST(E2eModel, DetectionProtectsWhatTheDbcsConventionsIdentifyAndTheMapWins) {
  const Database db = parse_dbc(kToyotaDbc, "toyota_test.dbc");
  Model detected(&db, parse_mapping("[e2e]\ndetect = true\n", "d.map"));
  ASSERT_EQ(detected.e2e().entries().size(), 1u);
  EXPECT_EQ(detected.e2e().entries()[0].message.spec.checksum, ChecksumKind::Toyota);
  EXPECT_EQ(detected.used_ids(), (std::vector<std::pair<std::uint32_t, bool>>{{180, false}}));  // joins the kernel filter
  Model configured(&db, parse_mapping("[e2e]\ndetect = true\n[e2e SPEED]\nchecksum = none\n", "d.map"));
  ASSERT_EQ(configured.e2e().entries().size(), 1u);
  EXPECT_EQ(configured.e2e().entries()[0].message.spec.checksum, ChecksumKind::None);
  Model off(&db, parse_mapping("[Vehicle.Speed]\nsource = SPEED.SPEED\ntimeout = 100ms\n", "d.map"));
  EXPECT_TRUE(off.e2e().empty());  // nothing configured: every frame believed, as before
}

TEST(E2eModel, UnknownMessagesAndSignalsInTheMapAreErrorsAtStart) {
  const Database db = parse_dbc(kToyotaDbc, "toyota_test.dbc");
  EXPECT_THROW(Model(&db, parse_mapping("[e2e NOPE]\nchecksum = toyota\n", "x.map")), MappingError);
  EXPECT_THROW(Model(&db, parse_mapping("[e2e SPEED]\nchecksum = honda\n", "x.map")), MappingError);  // not a nibble
  EXPECT_THROW(Model(&db, parse_mapping("[e2e PLAIN]\nchecksum = toyota\n", "x.map")), MappingError);  // no CHECKSUM
}

TEST(E2eHealthReport, LogsRefusalsAtMostOnceASecondAndAMismatchOnce) {
  HealthReport report("log:x");
  Trace trace("");
  std::ostringstream err;
  BusHealth bus;
  bus.e2e.push_back(E2eHealth{"SPEED", 10, 2, 2, 0, 0, 0, false});
  report.update(bus, 0, 1'000'000'000, err, trace);
  bus.e2e[0] = E2eHealth{"SPEED", 20, 4, 4, 0, 0, 0, false};
  report.update(bus, 0, 1'500'000'000, err, trace);  // within the second: no line
  bus.e2e[0] = E2eHealth{"SPEED", 30, 25, 25, 0, 0, 0, true};
  report.update(bus, 0, 2'100'000'000, err, trace);
  report.update(bus, 0, 2'200'000'000, err, trace);  // the mismatch is not repeated
  const std::string log = err.str();
  EXPECT_NE(log.find("log:x: e2e: 2 frame(s) refused (not used: SPEED 2)"), std::string::npos) << log;
  EXPECT_NE(log.find("log:x: e2e: 23 frame(s) refused (not used: SPEED 23)"), std::string::npos) << log;
  EXPECT_EQ(log.find("4 frame(s)"), std::string::npos) << log;
  const auto first = log.find("SPEED: likely configuration mismatch: 25 of 30 frames refused");
  EXPECT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find("likely configuration mismatch", first + 20), std::string::npos) << log;
  EXPECT_NE(report.stats_text().find("; e2e: SPEED 25 of 30 refused (25 checksum"), std::string::npos) << report.stats_text();
}

}  // namespace
}  // namespace meter::controller
