// DBC value names in maps: `map = D:127, ...` and `lit_when = ...` by VAL_ name, resolved against
// the DBC at start-up; an unknown name is an error naming the map line, the signal and the names.
#include <gtest/gtest.h>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/value_names.hpp"
#include "meter/controller/model/model.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
using meter::protocol::SignalStatus;
namespace sig = meter::protocol::sig;

namespace {

// An automatic's selector (VAL_ names as opendbc writes them) and a turn-signal state.
const std::string kNamedDbc = std::string(kDbc) +
                              "BO_ 768 Gearbox: 8 TCM\n"
                              " SG_ PRNDL : 0|4@1+ (1,0) [0|15] \"\" ICL\n"
                              " SG_ Turn : 8|2@1+ (1,0) [0|3] \"\" ICL\n"
                              "VAL_ 768 PRNDL 0 \"P\" 1 \"R\" 2 \"N\" 3 \"D\" 15 \"SNA\" ;\n"
                              "VAL_ 768 Turn 0 \"off\" 1 \"left\" 2 \"right\" 3 \"hazard lights\" ;\n";

const char* kGearMap =
    "[Vehicle.Powertrain.Transmission.CurrentGear]\n"
    "source = Gearbox.PRNDL\n"
    "map = D:127, N:0, R:-1, P:126\n"
    "timeout = none\n";

}  // namespace

TEST(MappingValueNames, ParseKeepsNamesAndNumbersApart) {
  Mapping m = parse_mapping("[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = A.b\n"
                            "map = D:127, 14:-1 15:126, \"3\":5, clutch released:1\n");
  const auto& o = m.outputs[0];
  ASSERT_EQ(o.remap.size(), 2u);  // 14 and 15 (space-separated pairs as before value names)
  EXPECT_EQ(o.remap[1], (std::pair<double, double>{15, 126}));
  ASSERT_EQ(o.remap_names.size(), 3u);
  EXPECT_EQ(o.remap_names[0].name, "D");
  EXPECT_EQ(o.remap_names[0].to, 127);
  EXPECT_EQ(o.remap_names[1].name, "3");  // quoted: a name, not the number 3
  EXPECT_EQ(o.remap_names[2].name, "clutch released");
  EXPECT_EQ(o.remap_names[2].line, 3);
  EXPECT_THROW(parse_mapping("[Vehicle.Speed]\nsource = A.b\nlit_when = left\n"), MappingError);  // not a telltale
  EXPECT_THROW(parse_mapping("[Vehicle.Speed]\nsource = A.b\nmap = \"D:1\n"), MappingError);     // open quote
}

TEST(MappingValueNames, GearByNameIncludingDriveAt127) {
  // VSS CurrentGear uses 127 for Drive: the catalog range must hold it.
  Database db = parse_dbc(kNamedDbc, "t.dbc");
  Model m(&db, parse_mapping(kGearMap, "gear.map"));
  m.start(0);
  const std::pair<std::uint8_t, double> cases[] = {{3, 127}, {2, 0}, {1, -1}, {0, 126}};
  std::int64_t t = 0;
  for (const auto& [raw, want] : cases) {
    t += 10 * ms;
    m.on_frame(frame(768, t, {raw, 0, 0, 0, 0, 0, 0, 0}));
    m.update(t + ms);
    EXPECT_EQ(m.output(sig::kCurrentGear)->status, SignalStatus::Valid) << "raw " << int(raw);
    EXPECT_EQ(m.output(sig::kCurrentGear)->value, want) << "raw " << int(raw);
  }
}

TEST(MappingValueNames, TelltaleLitWhenNamedStates) {
  Database db = parse_dbc(kNamedDbc, "t.dbc");
  Mapping map = parse_mapping("[Cluster.Telltale.TurnLeft]\nsource = Gearbox.Turn\n"
                              "lit_when = left, hazard lights\ntimeout = none\n", "turn.map");
  resolve_value_names(map, &db);
  const OutputMapping& o = map.outputs[0];
  EXPECT_EQ(convert_value(o, 0), 0.0);
  EXPECT_EQ(convert_value(o, 1), 1.0);
  EXPECT_EQ(convert_value(o, 2), 0.0);  // right: not this lamp
  EXPECT_EQ(convert_value(o, 3), 1.0);
}

TEST(MappingValueNames, UnknownNameNamesLineSignalAndTheDbcNames) {
  Database db = parse_dbc(kNamedDbc, "t.dbc");
  try {
    Model m(&db, parse_mapping("# gear\n[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = Gearbox.PRNDL\n"
                               "map = P:126, Drive:127\n", "gear.map"));
    FAIL() << "an unknown value name was accepted";
  } catch (const MappingError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("gear.map:4:"), std::string::npos) << w;
    EXPECT_NE(w.find("'Drive'"), std::string::npos) << w;
    EXPECT_NE(w.find("Gearbox.PRNDL"), std::string::npos) << w;
    EXPECT_NE(w.find("3 \"D\""), std::string::npos) << w;
  }
  // A signal without VAL_ table and a Modbus-only section say so.
  EXPECT_THROW(Model(&db, parse_mapping("[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = Speed.Gear\nmap = D:127\n")),
               MappingError);
}
