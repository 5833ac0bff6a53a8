// Applying a mapping, stage by stage, on plain data: no model, no socket, no clock.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/mapping/apply.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
using meter::protocol::SignalStatus;

namespace {

OutputMapping output(const std::string& body) {
  return parse_mapping("[Vehicle.Speed]\n" + body, "t.map").outputs.at(0);
}

SourceReading fresh(double value, std::int64_t rx_ns = 0) {
  SourceReading r;
  r.received = true;
  r.last_rx_ns = rx_ns;
  r.value = value;
  r.valid = true;
  return r;
}

}  // namespace

TEST(MappingApply, DeriveTimeoutsFromTheSlowestCycle) {
  const OutputMapping m = output("source = A.x, B.y\n");
  const std::vector<std::optional<int>> cycles{20, 100};
  const SourceTimeouts t = derive_timeouts(m, cycles, "t.map");
  EXPECT_EQ(t.later_ns, 300 * ms);   // 3 cycles of the slowest source
  EXPECT_EQ(t.first_ns, 1000 * ms);  // 10 cycles, but at least 1 s
  const std::vector<std::optional<int>> slow{500};
  EXPECT_EQ(derive_timeouts(output("source = A.x\n"), slow, "t.map").first_ns, 5000 * ms);
}

TEST(MappingApply, DeriveTimeoutsExplicitNoneAndMissingCycle) {
  const std::vector<std::optional<int>> none{std::nullopt};
  const SourceTimeouts t = derive_timeouts(output("source = A.x\ntimeout = 250ms\n"), none, "t.map");
  EXPECT_EQ(t.later_ns, 250 * ms);
  EXPECT_EQ(t.first_ns, 1000 * ms);
  const SourceTimeouts first = derive_timeouts(output("source = A.x\ntimeout = 2s\nfirst_timeout = 0.5\n"), none, "t.map");
  EXPECT_EQ(first.later_ns, 2000 * ms);
  EXPECT_EQ(first.first_ns, 500 * ms);
  const SourceTimeouts off = derive_timeouts(output("source = A.x\ntimeout = none\n"), none, "t.map");
  EXPECT_LT(off.later_ns, 0);
  EXPECT_LT(off.first_ns, 0);
  try {
    derive_timeouts(output("source = A.x\n"), none, "t.map");
    ADD_FAILURE() << "timeout = auto without a cycle time must fail";
  } catch (const MappingError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("A.x has no GenMsgCycleTime"), std::string::npos) << e.what();
  }
}

TEST(MappingApply, CombineFirstMeanMinMax) {
  const std::vector<SourceReading> s{fresh(10), fresh(30), fresh(20)};
  const SourceTimeouts none;
  EXPECT_DOUBLE_EQ(combine_sources(output("source = A.x\n"), s, none, 0, 0).value, 10);
  EXPECT_EQ(combine_sources(output("source = A.x\n"), s, none, 0, 0).valid, 1);  // first stops at the first usable
  EXPECT_DOUBLE_EQ(combine_sources(output("source = A.x\ncombine = mean\n"), s, none, 0, 0).value, 20);
  EXPECT_DOUBLE_EQ(combine_sources(output("source = A.x\ncombine = min\n"), s, none, 0, 0).value, 10);
  const CombinedSources mx = combine_sources(output("source = A.x\ncombine = max\n"), s, none, 0, 0);
  EXPECT_DOUBLE_EQ(mx.value, 30);
  EXPECT_EQ(mx.valid, 3);
}

TEST(MappingApply, CombineCountsTimeoutsAndRangeActions) {
  SourceTimeouts t;
  t.later_ns = 100 * ms;
  t.first_ns = 480 * ms;
  SourceReading never;  // not received yet
  SourceReading stale = fresh(5, 0);
  SourceReading high = fresh(150, 400 * ms);
  high.out_of_range = true;
  high.range_min = 0;
  high.range_max = 100;
  const std::vector<SourceReading> s{never, stale, high};
  const OutputMapping mean = output("source = A.x\ncombine = mean\n");
  // Before the first timeout a missing source is just absent; the stale one has timed out.
  CombinedSources c = combine_sources(mean, s, t, 450 * ms, 0);
  EXPECT_EQ(c.timed_out, 1);
  EXPECT_EQ(c.invalid, 1);  // out of range = invalid by default
  EXPECT_EQ(c.valid, 0);
  c = combine_sources(mean, s, t, 490 * ms, 0);
  EXPECT_EQ(c.timed_out, 2);  // now the never-received source has timed out too
  c = combine_sources(output("source = A.x\nout_of_range = clamp\n"), s, t, 450 * ms, 0);
  EXPECT_DOUBLE_EQ(c.value, 100);
  c = combine_sources(output("source = A.x\nout_of_range = accept\n"), s, t, 450 * ms, 0);
  EXPECT_DOUBLE_EQ(c.value, 150);
}

TEST(MappingApply, ConvertScalesOffsetsAndRemaps) {
  EXPECT_DOUBLE_EQ(convert_value(output("source = A.x\nconvert = m/s->km/h\n"), 10), 36);
  EXPECT_DOUBLE_EQ(convert_value(output("source = A.x\nscale = 2\noffset = -1\n"), 3), 5);
  const OutputMapping remap = output("source = A.x\nscale = 2\nmap = 4:126, 6:-1\n");
  EXPECT_DOUBLE_EQ(convert_value(remap, 2), 126);  // the remap applies to the scaled value
  EXPECT_DOUBLE_EQ(convert_value(remap, 3), -1);
  EXPECT_DOUBLE_EQ(convert_value(remap, 4), 8);
}

TEST(MappingApply, StatusPrecedenceAndNonFiniteResults) {
  const OutputMapping m = output("source = A.x\n");
  EXPECT_EQ(mapped_value(m, CombinedSources{1, 1, 1, 7}).status, SignalStatus::Valid);
  EXPECT_EQ(mapped_value(m, CombinedSources{0, 1, 1, 0}).status, SignalStatus::Invalid);
  EXPECT_EQ(mapped_value(m, CombinedSources{0, 0, 1, 0}).status, SignalStatus::TimedOut);
  EXPECT_EQ(mapped_value(m, CombinedSources{}).status, SignalStatus::NotAvailable);
  const OutputValue inf = mapped_value(m, CombinedSources{1, 0, 0, std::numeric_limits<double>::infinity()});
  EXPECT_EQ(inf.status, SignalStatus::Invalid);
  EXPECT_EQ(inf.value, 0.0);
}

TEST(MappingApply, TimeoutActionsHoldSubstituteInvalid) {
  const OutputValue timed_out{0.0, SignalStatus::TimedOut};
  const OutputMapping hold = output("source = A.x\non_timeout = hold\n");
  EXPECT_EQ(apply_timeout_action(hold, timed_out, 42.0).status, SignalStatus::Valid);
  EXPECT_DOUBLE_EQ(apply_timeout_action(hold, timed_out, 42.0).value, 42);
  EXPECT_EQ(apply_timeout_action(hold, timed_out, std::nullopt).status, SignalStatus::TimedOut);  // nothing to hold
  const OutputValue sub = apply_timeout_action(output("source = A.x\non_timeout = substitute 3\n"), timed_out, 42.0);
  EXPECT_EQ(sub.status, SignalStatus::Valid);
  EXPECT_DOUBLE_EQ(sub.value, 3);
  const OutputValue inv = apply_timeout_action(output("source = A.x\n"), timed_out, 42.0);
  EXPECT_EQ(inv.status, SignalStatus::TimedOut);
  EXPECT_DOUBLE_EQ(inv.value, 42);  // the gauge may keep its last position in the timeout look
  const OutputValue valid{5.0, SignalStatus::Valid};
  EXPECT_DOUBLE_EQ(apply_timeout_action(hold, valid, 42.0).value, 5);  // only timeouts are touched
}

TEST(MappingApply, MapOutputEndToEnd) {
  const OutputMapping m = output("source = A.x, B.y\ncombine = mean\nconvert = m/s->km/h\non_timeout = hold\n");
  SourceTimeouts t;
  t.later_ns = 100 * ms;
  const std::vector<SourceReading> s{fresh(10, 0), fresh(20, 0)};
  OutputValue v = map_output(m, s, t, 50 * ms, 0, std::nullopt);
  EXPECT_EQ(v.status, SignalStatus::Valid);
  EXPECT_DOUBLE_EQ(v.value, 54);
  v = map_output(m, s, t, 500 * ms, 0, 54.0);
  EXPECT_EQ(v.status, SignalStatus::Valid);  // both timed out: held
  EXPECT_DOUBLE_EQ(v.value, 54);
}

TEST(MappingSources, ResolveDecodeAndUsedIds) {
  Database db = parse_dbc(kDbc, "t.dbc");
  Mapping map = parse_mapping("[Vehicle.Speed]\nsource = Speed.WheelA, Speed.WheelB\n[Vehicle.Exterior.AirTemperature]\nsource = Temps.Outside\n", "t.map");
  SourceTable table(&db, map);
  const std::vector<int> speed = table.add(map.outputs[0]);
  ASSERT_EQ(speed.size(), 2u);
  EXPECT_EQ(table.add(map.outputs[0]), speed);  // known keys are not added twice
  const std::vector<int> outside = table.add(map.outputs[1]);
  EXPECT_EQ(table[speed[0]].cycle_ms, 20);
  EXPECT_EQ(table[outside[0]].cycle_ms, 100);
  const std::vector<std::pair<std::uint32_t, bool>> ids{{256, false}, {512, false}};
  EXPECT_EQ(table.used_ids(), ids);

  EXPECT_EQ(table.on_frame(frame(256, 5 * ms, {0x10, 0x27, 0x20, 0x4E, 0, 0, 0, 0})), FrameUse::Mapped);
  EXPECT_TRUE(table[speed[0]].reading.received);
  EXPECT_DOUBLE_EQ(table[speed[0]].reading.value, 100.0);
  EXPECT_DOUBLE_EQ(table[speed[1]].reading.value, 200.0);
  EXPECT_TRUE(table[speed[1]].reading.out_of_range);  // DBC range [0|100]
  EXPECT_TRUE(table[speed[1]].reading.valid);         // still usable: the mapping decides
  EXPECT_EQ(table[speed[0]].reading.last_rx_ns, 5 * ms);
  EXPECT_EQ(table.on_frame(frame(0x300, 0, {0})), FrameUse::UnknownId);
  CanFrame err = frame(1, 0, {});
  err.error = true;
  EXPECT_EQ(table.on_frame(err), FrameUse::ErrorFrame);
  EXPECT_FALSE(table.on_value("modbus.none", 1, true, 0));

  try {
    Mapping bad = parse_mapping("[Vehicle.Speed]\nsource = Nope.X\n", "t.map");
    SourceTable(&db, bad).add(bad.outputs[0]);
    ADD_FAILURE();
  } catch (const MappingError& e) {
    EXPECT_NE(std::string(e.what()).find("no message 'Nope'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(resolve_dbc_source(nullptr, "Speed.WheelA", "t.map", 1), MappingError);  // needs a DBC
  const DbcSource src = resolve_dbc_source(&db, "Temps.Coolant", "t.map", 1);
  EXPECT_EQ(src.dbc_signal().name, "Coolant");
}
