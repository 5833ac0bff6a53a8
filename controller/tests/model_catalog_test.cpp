// The model finds the signals it treats specially (speed, odometer, trip, ignition) by VSS name in
// the loaded catalog, not by the shipped catalog's ids: a catalog that numbers them differently
// drives the odometer just the same, and one that lacks a signal the mapping needs is refused.
#include <gtest/gtest.h>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/protocol/catalog.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
namespace protocol = meter::protocol;

namespace {

// Restores the shipped catalog after each test.
class ModelCatalog : public ::testing::Test {
 protected:
  void TearDown() override { protocol::set_active_catalog(protocol::default_catalog()); }

  static void use(const std::string& json, const std::string& file) {
    auto r = protocol::parse_catalog(json, file);
    ASSERT_TRUE(r.catalog) << r.error;
    protocol::set_active_catalog(r.catalog);
  }
};

std::string leaf(const std::string& name, int id, const std::string& extra, const std::string& datatype = "float") {
  return "\"" + name + "\": {\"type\": \"sensor\", \"datatype\": \"" + datatype + "\", \"meter_id\": " +
         std::to_string(id) + ", " + extra + "}";
}

// Speed, odometer, trip and ignition under ids the shipped catalog does not use (it has 1..36).
std::string renumbered(bool with_trip) {
  return "{\"Vehicle\": {\"type\": \"branch\", \"children\": {" + leaf("Speed", 500, "\"min\": 0, \"max\": 300") + ", " +
         leaf("TraveledDistance", 501, "\"min\": 0, \"max\": 9999999, \"meter_kind\": \"counter\"") + ", " +
         (with_trip ? leaf("TripMeterReading", 502, "\"min\": 0, \"max\": 99999.9, \"meter_kind\": \"counter\"") + ", "
                    : std::string()) +
         leaf("LowVoltageSystemState", 503, "\"min\": 0, \"max\": 5, \"meter_kind\": \"enum\"", "uint8") +
         "}}}";
}

const char* kMap = "[Vehicle.Speed]\nsource = Speed.WheelA\nconvert = m/s->km/h\n[Vehicle.TraveledDistance]\naccumulate = speed\n";

}  // namespace

TEST_F(ModelCatalog, OdometerAndTripFollowTheirNamesNotTheShippedIds) {
  use(renumbered(true), "renumbered.vss.json");
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping(kMap));
  m.start(0);
  // 25 m/s = 90 km/h for 10 s in 10 ms ticks = 250 m, as in Model.OdometerFromSpeedPersistsAndReloads.
  for (std::int64_t t = 0; t <= 10000; t += 10) {
    m.on_frame(frame(256, t * ms, {0xC4, 0x09, 0, 0, 0, 0, 0, 0}));
    m.update(t * ms);
  }
  EXPECT_EQ(m.odometer().total_um(), 250LL * 1000000);
  ASSERT_NE(m.output(501), nullptr);
  ASSERT_NE(m.output(502), nullptr) << "the trip meter comes with the odometer";
  EXPECT_NEAR(m.output(501)->value, 0.2, 1e-12);
  EXPECT_NEAR(m.output(502)->value, 0.2, 1e-12);
  EXPECT_NEAR(m.output(500)->value, 90.0, 1e-9);
  EXPECT_EQ(m.output(protocol::sig::kOdometer), nullptr);  // the shipped id means nothing here
}

TEST_F(ModelCatalog, AnOdometerWithoutATripInTheCatalogIsRefusedNamingTheCatalog) {
  use(renumbered(false), "no-trip.vss.json");
  Database db = parse_dbc(kDbc, "t.dbc");
  try {
    Model m(&db, parse_mapping(kMap));
    ADD_FAILURE() << "a model with an odometer but no trip signal was built";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "signal catalog no-trip.vss.json has no signal Vehicle.TripMeterReading (needed for the "
                           "trip meter that comes with the odometer)");
  }
}

TEST_F(ModelCatalog, AMappingSectionTheCatalogLacksNamesTheCatalogFile) {
  use(renumbered(true), "renumbered.vss.json");
  try {
    parse_mapping("[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = Speed.WheelA\n", "m.map");
    ADD_FAILURE() << "a section for a signal the catalog lacks was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("m.map:1: section [Vehicle.Powertrain.CombustionEngine.Speed]: expected a "
                                         "signal of the catalog renumbered.vss.json"),
              std::string::npos)
        << e.what();
  }
}
