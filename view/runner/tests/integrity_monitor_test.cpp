// The integrity monitor's judgement on plain data (no GL): faults name region, expected and
// seen; frozen regions (expected look changed, pixels did not); what counts as a change of look;
// the --inject-fault text; the log limit; the frames.csv columns.
#include "meter/runner/integrity_monitor.hpp"
#include "meter/runner/integrity_stage.hpp"

#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using bridge::SafetyKind;

bridge::SafetyRegion region(const std::string& name, SafetyKind kind, bridge::PixelRect rect) {
  bridge::SafetyRegion r;
  r.name = r.node = name;
  r.kind = kind;
  r.rect = rect;
  return r;
}

// A 4x4 lamp at (10, 20): every pixel is lamp; lit look green, dark look near black.
bridge::SafetyRegion lamp() {
  bridge::SafetyRegion r = region("TT_Test", SafetyKind::Telltale, {10, 20, 4, 4});
  r.telltale.mask.assign(16, 1);
  r.telltale.looks = {{"on", true, {0, 200, 0}}, {"off", false, {10, 10, 10}}};
  r.telltale.tolerance = 20;
  return r;
}

bridge::SafetyRegion readout() { return region("Text_Speed", SafetyKind::Readout, {40, 20, 4, 4}); }

engine::RegionExpectation lit(bool on) {
  engine::RegionExpectation e;
  e.known = true;
  e.lit = on;
  return e;
}

engine::RegionExpectation text(const std::string& t) {
  engine::RegionExpectation e;
  e.known = true;
  e.text = t;
  return e;
}

platform::Image fill(std::uint8_t r, std::uint8_t g, std::uint8_t b) { return platform::Image(4, 4, r, g, b); }

TEST(IntegrityJudge, ALampShowingTheWrongStateIsAFaultNamingRegionExpectedAndSeen) {
  bridge::IntegrityTable table;
  table.regions = {lamp()};
  std::vector<RegionMemory> memory;
  EXPECT_TRUE(judge_frame(table, {lit(true)}, {fill(0, 200, 0)}, memory).empty());
  const auto faults = judge_frame(table, {lit(false)}, {fill(0, 200, 0)}, memory);
  ASSERT_FALSE(faults.empty());
  EXPECT_EQ(faults[0].region, "TT_Test");
  EXPECT_FALSE(faults[0].frozen);
  EXPECT_FALSE(faults[0].expected.empty());
  EXPECT_FALSE(faults[0].seen.empty());
  EXPECT_GT(faults[0].difference, 20.0);
  EXPECT_NE(faults[0].describe().find("TT_Test (telltale): expected "), std::string::npos) << faults[0].describe();
}

TEST(IntegrityJudge, PixelsThatStayWhileTheExpectedLookChangesAreAFrozenRegion) {
  bridge::IntegrityTable table;
  table.regions = {readout()};
  std::vector<RegionMemory> memory;
  EXPECT_TRUE(judge_frame(table, {text("82")}, {fill(1, 2, 3)}, memory).empty());
  EXPECT_TRUE(judge_frame(table, {text("82")}, {fill(1, 2, 3)}, memory).empty()) << "same text, same pixels";
  const auto faults = judge_frame(table, {text("83")}, {fill(1, 2, 3)}, memory);
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_TRUE(faults[0].frozen);
  EXPECT_EQ(faults[0].expected, "\"83\" (was \"82\")");
  // Still the old pixels a frame later: still frozen; new pixels: fine again.
  EXPECT_EQ(judge_frame(table, {text("84")}, {fill(1, 2, 3)}, memory).size(), 1u);
  EXPECT_TRUE(judge_frame(table, {text("84")}, {fill(9, 2, 3)}, memory).empty());
}

TEST(IntegrityJudge, AFrozenLampIsCaughtAsFrozenAndAsTheWrongState) {
  bridge::IntegrityTable table;
  table.regions = {lamp()};
  std::vector<RegionMemory> memory;
  EXPECT_TRUE(judge_frame(table, {lit(false)}, {fill(10, 10, 10)}, memory).empty());
  const auto faults = judge_frame(table, {lit(true)}, {fill(10, 10, 10)}, memory);
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_FALSE(faults[0].frozen);
  EXPECT_TRUE(faults[1].frozen);
}

TEST(IntegrityJudge, RegionsWithoutAnExpectationYetAreNotJudged) {
  bridge::IntegrityTable table;
  table.regions = {lamp()};
  std::vector<RegionMemory> memory;
  EXPECT_TRUE(judge_frame(table, {engine::RegionExpectation{}}, {fill(255, 0, 255)}, memory).empty());
}

TEST(IntegrityJudge, ANeedleTurningLessThanADegreeOrItsToleranceIsNoChangeOfLook) {
  bridge::SafetyRegion needle;
  needle.kind = SafetyKind::Needle;
  needle.needle.tolerance_deg = 1.5;
  engine::RegionExpectation a, b;
  a.known = b.known = true;
  a.angle_deg = 10.0;
  b.angle_deg = 11.4;
  EXPECT_FALSE(look_changed(needle, a, b));
  b.angle_deg = 11.6;
  EXPECT_TRUE(look_changed(needle, a, b));
  needle.needle.tolerance_deg = 0.2;
  b.angle_deg = 10.9;
  EXPECT_FALSE(look_changed(needle, a, b)) << "below 1 degree a needle may not move a pixel";
}

engine::Scene scene_with_lamp() {
  engine::Scene s;
  s.source_name = "test.msp";
  bridge::Node n;
  n.name = "TT_Test";
  s.nodes.push_back(n);
  s.integrity.width = 64, s.integrity.height = 48;
  s.integrity.regions = {lamp()};
  return s;
}

TEST(FaultSchedule, ParsesKindRegionAndFrames) {
  const auto scene = scene_with_lamp();
  const auto s = parse_fault_schedule("drop:TT_Test@30-40", scene, 48);
  EXPECT_EQ(s.fault.kind, engine::FaultKind::DropDraw);
  EXPECT_EQ(s.fault.node, 0);
  EXPECT_EQ(s.fault.box, (platform::PixelRegion{10, 48 - 20 - 4, 4, 4}));  // GL rows count from the bottom
  EXPECT_EQ(s.first, 30u);
  EXPECT_EQ(s.last, 40u);
  const auto stuck = parse_fault_schedule("stuck@5", scene, 48);
  EXPECT_EQ(stuck.fault.kind, engine::FaultKind::StuckFrame);
  EXPECT_FALSE(stuck.last.has_value());
  EXPECT_FALSE(stuck.display_copy_lost);
  // The display's copy lost: no region, nothing for the renderer to inject.
  const auto display = parse_fault_schedule("display@20-40", scene, 48);
  EXPECT_TRUE(display.display_copy_lost);
  EXPECT_EQ(display.first, 20u);
  EXPECT_EQ(display.last, 40u);
}

TEST(FaultSchedule, BadTextsAreNamed) {
  const auto scene = scene_with_lamp();
  auto message = [&](const std::string& t) {
    try {
      parse_fault_schedule(t, scene, 48);
    } catch (const ViewError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("drop:TT_Test").find("expected KIND[:REGION]@FIRST[-LAST]"), std::string::npos);
  EXPECT_NE(message("smear:TT_Test@3").find("unknown fault \"smear\""), std::string::npos);
  EXPECT_NE(message("drop:TT_Nope@3").find("no safety region \"TT_Nope\" in test.msp"), std::string::npos);
  EXPECT_NE(message("drop:TT_Test@x").find("\"x\" is not a frame number"), std::string::npos);
  EXPECT_NE(message("drop:TT_Test@9-3").find("the last frame is before the first"), std::string::npos);
}

TEST(FaultLogLimit, FirstFaultOfEachRegionThenOneLinePerSecond) {
  FaultLogLimit limit;
  const auto t0 = FaultLogLimit::Clock::time_point{} + std::chrono::hours(1);
  EXPECT_TRUE(limit.admit("a", t0));
  EXPECT_TRUE(limit.admit("b", t0));
  EXPECT_FALSE(limit.admit("a", t0 + std::chrono::milliseconds(500)));
  EXPECT_TRUE(limit.admit("a", t0 + std::chrono::milliseconds(1000)));
  EXPECT_EQ(limit.suppressed(), 1u);
}

TEST(FramesCsv, IntegrityColumnsComeLastOnlyWhenTheMonitorIsOn) {
  const auto dir = testing::scratch_dir();
  engine::Binding b;
  b.kind = engine::BindingKind::Visibility;
  b.signal = "Cluster.Telltale.ABS";
  b.node = "abs";
  engine::BindingState st;
  st.value = 1;
  {
    FramesCsv off(dir / "off.csv", {b});
    off.row(0, 0.0, "f.png", true, true, {st});
    FramesCsv on(dir / "on.csv", {b}, true);
    const IntegrityCells cells{1, 3, "TT_ABS (telltale): expected on, seen off, difference 80.00"};
    on.row(0, 0.0, "f.png", true, true, {st}, &cells);
    on.row(1, 0.0, "g.png", true, true, {st});
  }
  const auto off = testing::read_lines(dir / "off.csv");
  EXPECT_EQ(off[0].find("integrity"), std::string::npos);
  const auto on = testing::read_lines(dir / "on.csv");
  ASSERT_EQ(on.size(), 3u);
  EXPECT_NE(on[0].find(",integrity_faults,integrity_total,integrity_fault"), std::string::npos) << on[0];
  EXPECT_NE(on[1].find(",1,3,\"TT_ABS (telltale): expected on, seen off, difference 80.00\""), std::string::npos) << on[1];
  EXPECT_NE(on[2].find(",0,0,\"\""), std::string::npos) << on[2];
}

}  // namespace
}  // namespace meter::runner
