// Mapping sources over several inputs (buses): which input's DBC a source resolves against, the
// errors for unknown inputs and ambiguous messages, and frames decoded by their own input's DBC.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;

namespace {

// A second bus: an engine message of its own, and a message named like the body bus's "Speed"
// (with another id and layout), so an unqualified Speed.* is ambiguous.
const char* kChassisDbc =
    "BO_ 768 Engine: 8 ECU\n"
    " SG_ Rpm : 0|16@1+ (1,0) [0|8000] \"rpm\" ICL\n"
    "BO_ 257 Speed: 8 ECU\n"
    " SG_ WheelA : 0|16@1+ (0.1,0) [0|300] \"km/h\" ICL\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 768 10;\n";

struct TwoBuses {
  Database body = parse_dbc(kDbc, "body.dbc");
  Database chassis = parse_dbc(kChassisDbc, "chassis.dbc");
  std::vector<InputDbc> inputs{{"body", &body}, {"chassis", &chassis}, {"pump", nullptr}};
};

std::string error_of(const std::vector<InputDbc>& inputs, const std::string& key) {
  try {
    resolve_input_source(inputs, key, "v.map", 7);
  } catch (const MappingError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(MappingInputs, QualifiedAndUniqueSourcesResolveToTheirInput) {
  TwoBuses b;
  InputSource s = resolve_input_source(b.inputs, "chassis.Speed.WheelA", "v.map", 1);
  EXPECT_EQ(s.input, 1);
  EXPECT_EQ(s.dbc.message->id, 257u);
  s = resolve_input_source(b.inputs, "body.Speed.WheelA", "v.map", 1);
  EXPECT_EQ(s.input, 0);
  EXPECT_EQ(s.dbc.message->id, 256u);
  // Only the chassis DBC has Engine: the input need not be named.
  s = resolve_input_source(b.inputs, "Engine.Rpm", "v.map", 1);
  EXPECT_EQ(s.input, 1);
  EXPECT_EQ(s.dbc.dbc_signal().name, "Rpm");
  s = resolve_input_source(b.inputs, "Temps.Outside", "v.map", 1);
  EXPECT_EQ(s.input, 0);
}

TEST(MappingInputs, ErrorsNameTheMapLineAndWhatIsWrong) {
  TwoBuses b;
  const std::string ambiguous = error_of(b.inputs, "Speed.WheelA");
  EXPECT_TRUE(contains(ambiguous, "v.map:7: source Speed.WheelA is ambiguous")) << ambiguous;
  EXPECT_TRUE(contains(ambiguous, "inputs body and chassis")) << ambiguous;
  EXPECT_TRUE(contains(ambiguous, "body.Speed.WheelA")) << ambiguous;

  const std::string unknown = error_of(b.inputs, "brakes.Speed.WheelA");
  EXPECT_TRUE(contains(unknown, "v.map:7: source brakes.Speed.WheelA: no input named 'brakes'")) << unknown;
  EXPECT_TRUE(contains(unknown, "body (body.dbc), chassis (chassis.dbc), pump (no DBC)")) << unknown;

  const std::string no_dbc = error_of(b.inputs, "pump.Speed.WheelA");
  EXPECT_TRUE(contains(no_dbc, "v.map:7: source pump.Speed.WheelA: input 'pump' has no DBC")) << no_dbc;

  const std::string nowhere = error_of(b.inputs, "Doors.Open");
  EXPECT_TRUE(contains(nowhere, "v.map:7: source Doors.Open: no input's DBC has a message 'Doors'")) << nowhere;
  // An input name followed by a signal name alone: the message is missing.
  const std::string half = error_of(b.inputs, "body.WheelA");
  EXPECT_TRUE(contains(half, "'body' is an input: expected body.Message.Signal")) << half;

  const std::string no_signal = error_of(b.inputs, "chassis.Engine.Torque");
  EXPECT_TRUE(contains(no_signal, "v.map:7: source chassis.Engine.Torque: message Engine has no signal 'Torque'")) << no_signal;
}

TEST(MappingInputs, OneInputKeepsTheSingleDbcMeaning) {
  Database db = parse_dbc(kDbc, "t.dbc");
  const std::vector<InputDbc> one{{"", &db}};
  EXPECT_EQ(resolve_input_source(one, "Speed.WheelB", "t.map", 1).dbc.dbc_signal().name, "WheelB");
  EXPECT_TRUE(contains(error_of(one, "Nope.X"), "v.map:7: source Nope.X: the DBC t.dbc has no message 'Nope'"));
  EXPECT_TRUE(contains(error_of(one, "body.Speed.WheelA"), "no input named 'body'"));
  EXPECT_TRUE(contains(error_of({{"", nullptr}}, "Speed.WheelA"), "needs a DBC (--dbc)"));
  // A single named input may be named or not.
  const std::vector<InputDbc> named{{"body", &db}};
  EXPECT_EQ(resolve_input_source(named, "body.Speed.WheelA", "t.map", 1).dbc.message->id, 256u);
  EXPECT_EQ(resolve_input_source(named, "Speed.WheelA", "t.map", 1).dbc.message->id, 256u);
}

TEST(MappingInputs, FramesDecodeWithTheirOwnInputsDbc) {
  TwoBuses b;
  Mapping map = parse_mapping(
      "[Vehicle.Speed]\nsource = body.Speed.WheelA, chassis.Speed.WheelA\ncombine = max\n"
      "[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = Engine.Rpm\n",
      "v.map");
  SourceTable table(b.inputs, map);
  const std::vector<int> speed = table.add(map.outputs[0]);
  const std::vector<int> rpm = table.add(map.outputs[1]);
  const std::vector<std::pair<std::uint32_t, bool>> body_ids{{256, false}}, chassis_ids{{257, false}, {768, false}};
  EXPECT_EQ(table.used_ids(0), body_ids);
  EXPECT_EQ(table.used_ids(1), chassis_ids);
  EXPECT_TRUE(table.used_ids(2).empty());

  // 0x300 raw on both: body Speed.WheelA = 7.68 m/s at 0.01, chassis Speed.WheelA = 76.8 km/h at 0.1.
  CanFrame on_body = frame(256, 5 * ms, {0x00, 0x03});
  CanFrame on_chassis = frame(257, 6 * ms, {0x00, 0x03});
  on_chassis.input = 1;
  EXPECT_EQ(table.on_frame(on_body), FrameUse::Mapped);
  EXPECT_EQ(table.on_frame(on_chassis), FrameUse::Mapped);
  EXPECT_DOUBLE_EQ(table[speed[0]].reading.value, 7.68);
  EXPECT_DOUBLE_EQ(table[speed[1]].reading.value, 76.8);
  EXPECT_EQ(table[speed[1]].reading.last_rx_ns, 6 * ms);

  // The engine id on the body bus is not the chassis engine: the body DBC has no 768.
  CanFrame engine_on_body = frame(768, 7 * ms, {0xE8, 0x03});
  EXPECT_EQ(table.on_frame(engine_on_body), FrameUse::UnknownId);
  EXPECT_FALSE(table[rpm[0]].reading.received);
  CanFrame engine = engine_on_body;
  engine.input = 1;
  EXPECT_EQ(table.on_frame(engine), FrameUse::Mapped);
  EXPECT_DOUBLE_EQ(table[rpm[0]].reading.value, 1000.0);
  // A frame of an input without a DBC (or no such input) is not decoded.
  engine.input = 2;
  EXPECT_EQ(table.on_frame(engine), FrameUse::Ignored);
  engine.input = 9;
  EXPECT_EQ(table.on_frame(engine), FrameUse::Ignored);
}
