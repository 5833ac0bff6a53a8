// Deadline monitoring per signal: a signal on one page of a multiplexed message arrives once per
// round of pages, so its 'timeout = auto' deadline follows its page's period, not the message cycle.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/signal_period.hpp"
#include "meter/controller/model/model.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
using meter::protocol::SignalStatus;
namespace sig = meter::protocol::sig;

namespace {

// An N-page message at 10 ms: the multiplexor in byte 0, page 0 carries Coolant, page N-1 carries
// Outside (both in byte 1), every other page a filler signal.
std::string paged_dbc(int pages) {
  std::string d = "BO_ 768 Paged: 8 ECU\n SG_ Page M : 0|8@1+ (1,0) [0|255] \"\" ICL\n";
  d += " SG_ Coolant m0 : 8|8@1+ (1,-40) [-40|200] \"C\" ICL\n";
  for (int p = 1; p < pages - 1; ++p)
    d += " SG_ Fill" + std::to_string(p) + " m" + std::to_string(p) + " : 8|8@1+ (1,0) [0|255] \"\" ICL\n";
  d += " SG_ Outside m" + std::to_string(pages - 1) + " : 8|8@1+ (1,-40) [-40|80] \"C\" ICL\n";
  d += "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\nBA_ \"GenMsgCycleTime\" BO_ 768 10;\n";
  return d;
}

const char* kPagedMap =
    "[Vehicle.Powertrain.CombustionEngine.ECT]\nsource = Paged.Coolant\ntimeout = auto\non_timeout = substitute 999\n"
    "[Vehicle.Exterior.AirTemperature]\nsource = Paged.Outside\ntimeout = auto\non_timeout = substitute 999\n";

constexpr std::int64_t kCycle = 10 * ms;

// Frame k of the round robin, sent at k * 10 ms with a deterministic jitter of -1..+1 ms (a bus
// under load delays a frame by a fraction of its cycle; AUTOSAR COM's deadline must tolerate it).
CanFrame page_frame(int pages, std::int64_t k) {
  const std::int64_t jitter = ((k * 7) % 3 - 1) * ms;
  const auto page = static_cast<std::uint8_t>(k % pages);
  return frame(768, k * kCycle + jitter, {page, 100, 0, 0, 0, 0, 0, 0});  // 100 - 40 = 60 C
}

void expect_no_false_timeouts(int pages) {
  Database db = parse_dbc(paged_dbc(pages), "paged.dbc");
  Model m(&db, parse_mapping(kPagedMap));
  m.start(0);
  // 10 simulated minutes, the model ticking every 10 ms half-way between frames.
  constexpr std::int64_t kFrames = 10 * 60 * 100;
  int false_timeouts = 0, first_bad_tick = -1;
  for (std::int64_t k = 0; k < kFrames; ++k) {
    m.on_frame(page_frame(pages, k));
    const std::int64_t t = k * kCycle + 5 * ms;
    m.update(t);
    if (k < pages) continue;  // until every page has been seen once
    for (auto id : {sig::kCoolantTemp, sig::kOutsideTemp}) {
      const ModelOutput* o = m.output(id);
      if (o->status != SignalStatus::Valid || o->value != 60.0) {
        ++false_timeouts;
        if (first_bad_tick < 0) first_bad_tick = static_cast<int>(k);
      }
    }
  }
  EXPECT_EQ(false_timeouts, 0) << pages << " pages: first at frame " << first_bad_tick;
}

}  // namespace

TEST(SignalTimeouts, FourPageMultiplexTenMinutesNoFalseTimeouts) { expect_no_false_timeouts(4); }

TEST(SignalTimeouts, SixteenPageMultiplexTenMinutesNoFalseTimeouts) { expect_no_false_timeouts(16); }

// A page that really goes silent (its sender stops filling it while the other pages keep coming)
// is detected within its bound: 3 page periods after its last frame, plus the model's 10 ms tick;
// the other page's signal stays valid throughout.
TEST(SignalTimeouts, SilentPageDetectedWithinItsBound) {
  for (int pages : {4, 16}) {
    Database db = parse_dbc(paged_dbc(pages), "paged.dbc");
    Model m(&db, parse_mapping(kPagedMap));
    m.start(0);
    const std::int64_t page_period = pages * kCycle;
    std::int64_t last_outside = -1, detected = -1;
    for (std::int64_t k = 0; k < 20000; ++k) {
      const bool silent = k >= 10000;
      const CanFrame f = page_frame(pages, k);
      if (!silent || f.data[0] != pages - 1) {  // once silent, the last page no longer arrives
        m.on_frame(f);
        if (f.data[0] == pages - 1) last_outside = f.timestamp_ns;
      }
      const std::int64_t t = k * kCycle + 5 * ms;
      m.update(t);
      if (k >= pages) {
        ASSERT_EQ(m.output(sig::kCoolantTemp)->value, 60.0) << pages << " pages, frame " << k;
      }
      if (silent && detected < 0 && m.output(sig::kOutsideTemp)->value == 999.0) detected = t;
    }
    ASSERT_GT(detected, 0) << pages << " pages: the silent page was never detected";
    EXPECT_LE(detected - last_outside, 3 * page_period + kCycle) << pages << " pages";
    EXPECT_GT(detected - last_outside, 3 * page_period - kCycle) << pages << " pages: detected too early";
  }
}

TEST(SignalTimeouts, ArrivalPeriodOfPlainMultiplexedAndNestedSignals) {
  Database db = parse_dbc(
      "BO_ 769 Mux: 8 ECU\n"
      " SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ Plain : 56|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ A m0 : 8|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ B m1 : 8|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ C m2 : 8|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ D m3 : 8|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ Sub m3M : 16|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ S0 m0 : 24|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ S1 m1 : 24|8@1+ (1,0) [0|255] \"\" ICL\n"
      " SG_ Wide m0 : 32|8@1+ (1,0) [0|255] \"\" ICL\n"
      "BO_ 770 NoCycle: 8 ECU\n SG_ X : 0|8@1+ (1,0) [0|255] \"\" ICL\n"
      "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\nBA_ \"GenMsgCycleTime\" BO_ 769 10;\n"
      "SG_MUL_VAL_ 769 S0 Sub 0-0;\nSG_MUL_VAL_ 769 S1 Sub 1-1;\nSG_MUL_VAL_ 769 Wide Sel 0-1, 2-2;\n",
      "mux.dbc");
  const DbcMessage& m = *db.find("Mux");
  auto period = [&](const char* name) { return signal_period_ms(m, m.find_signal(name)); };
  EXPECT_EQ(period("Plain"), 10);  // every frame
  EXPECT_EQ(period("Sel"), 10);    // the multiplexor itself
  EXPECT_EQ(period("A"), 40);      // one of 4 pages
  EXPECT_EQ(period("Wide"), 20);   // on 3 of the 4 pages: at most 2 frames apart
  EXPECT_EQ(period("Sub"), 40);    // page 3, and a switch of its own
  EXPECT_EQ(period("S0"), 80);     // one of Sub's 2 pages, each every 40 ms
  EXPECT_EQ(signal_period_ms(*db.find("NoCycle"), 0), std::nullopt);
}
