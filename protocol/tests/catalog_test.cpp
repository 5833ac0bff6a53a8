// The catalog is the contract between controller and view: the shipped VSS JSON file keeps every
// id, name, unit, range and kind the compiled table had; the loader turns any bad file into an
// error naming the file, the JSON path and what was expected.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "ev_catalog.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::protocol {
namespace {

using nlohmann::json;

// Restores the process's active catalog after a test that replaces it.
struct ActiveCatalogGuard {
  std::shared_ptr<const Catalog> saved = active_catalog();
  ~ActiveCatalogGuard() { set_active_catalog(saved); }
};

TEST(Catalog, IdsUniqueSortedAndFindable) {
  std::set<SignalId> ids;
  std::set<std::string_view> names;
  SignalId previous = 0;
  for (const auto& s : catalog()) {
    EXPECT_TRUE(ids.insert(s.id).second) << s.id;
    EXPECT_TRUE(names.insert(s.name).second) << s.name;
    EXPECT_GT(s.id, previous) << s.name;
    previous = s.id;
    EXPECT_LE(s.min, s.max) << s.name;
    EXPECT_EQ(find_signal(s.id), &s);
    EXPECT_EQ(find_signal(s.name), &s);
  }
  EXPECT_EQ(find_signal(SignalId{999}), nullptr);
  EXPECT_EQ(find_signal("Vehicle.NoSuchThing"), nullptr);
}

// The shipped file is the old compiled table, entry for entry (CurrentGear now reaches 127 = Drive,
// as VSS numbers it): a view and a controller built before the catalog became data read the same
// ids the same way.
TEST(Catalog, ShippedFileKeepsEveryCompiledEntry) {
  using K = SignalKind;
  const std::vector<SignalInfo> expected = {
      {sig::kSpeed, "Vehicle.Speed", "km/h", 0.0, 300.0, K::Gauge},
      {sig::kEngineSpeed, "Vehicle.Powertrain.CombustionEngine.Speed", "rpm", 0.0, 10000.0, K::Gauge},
      {sig::kFuelLevel, "Vehicle.Powertrain.FuelSystem.RelativeLevel", "percent", 0.0, 100.0, K::Gauge},
      {sig::kCoolantTemp, "Vehicle.Powertrain.CombustionEngine.ECT", "celsius", -40.0, 150.0, K::Gauge},
      {sig::kCurrentGear, "Vehicle.Powertrain.Transmission.CurrentGear", "", -1.0, 127.0, K::Enum},
      {sig::kOdometer, "Vehicle.TraveledDistance", "km", 0.0, 9999999.0, K::Counter},
      {sig::kTrip, "Vehicle.TripMeterReading", "km", 0.0, 99999.9, K::Counter},
      {sig::kOutsideTemp, "Vehicle.Exterior.AirTemperature", "celsius", -40.0, 85.0, K::Gauge},
      {sig::kIgnition, "Vehicle.LowVoltageSystemState", "", 0.0, 5.0, K::Enum},
      {sig::kTurnLeft, "Cluster.Telltale.TurnLeft", "", 0.0, 1.0, K::Telltale},
      {sig::kTurnRight, "Cluster.Telltale.TurnRight", "", 0.0, 1.0, K::Telltale},
      {sig::kHighBeam, "Cluster.Telltale.HighBeam", "", 0.0, 1.0, K::Telltale},
      {sig::kLowBeam, "Cluster.Telltale.LowBeam", "", 0.0, 1.0, K::Telltale},
      {sig::kFrontFog, "Cluster.Telltale.FrontFog", "", 0.0, 1.0, K::Telltale},
      {sig::kParkingBrake, "Cluster.Telltale.ParkingBrake", "", 0.0, 1.0, K::Telltale},
      {sig::kBrakeFault, "Cluster.Telltale.BrakeFault", "", 0.0, 1.0, K::Telltale},
      {sig::kAbs, "Cluster.Telltale.ABS", "", 0.0, 1.0, K::Telltale},
      {sig::kAirbag, "Cluster.Telltale.Airbag", "", 0.0, 1.0, K::Telltale},
      {sig::kSeatBelt, "Cluster.Telltale.SeatBelt", "", 0.0, 1.0, K::Telltale},
      {sig::kOilPressure, "Cluster.Telltale.OilPressure", "", 0.0, 1.0, K::Telltale},
      {sig::kBattery, "Cluster.Telltale.Battery", "", 0.0, 1.0, K::Telltale},
      {sig::kCheckEngine, "Cluster.Telltale.CheckEngine", "", 0.0, 1.0, K::Telltale},
      {sig::kCoolantOverTemp, "Cluster.Telltale.CoolantTemp", "", 0.0, 1.0, K::Telltale},
      {sig::kEsc, "Cluster.Telltale.ESC", "", 0.0, 1.0, K::Telltale},
      {sig::kTpms, "Cluster.Telltale.TPMS", "", 0.0, 1.0, K::Telltale},
      {sig::kFuelLow, "Cluster.Telltale.FuelLow", "", 0.0, 1.0, K::Telltale},
      // The display settings (units, theme, brightness, page): looked up by name, no constants.
      {37, "Vehicle.Cabin.Infotainment.HMI.DistanceUnit", "", 0.0, 1.0, K::Enum},
      {38, "Vehicle.Cabin.Infotainment.HMI.TemperatureUnit", "", 0.0, 1.0, K::Enum},
      {39, "Vehicle.Cabin.Infotainment.HMI.DayNightMode", "", 0.0, 1.0, K::Enum},
      {40, "Vehicle.Cabin.Infotainment.HMI.Brightness", "percent", 0.0, 100.0, K::Gauge},
      {41, "Cluster.Page", "", 0.0, 7.0, K::Enum},
  };
  const auto shipped = default_catalog()->signals();
  ASSERT_EQ(shipped.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(shipped[i], expected[i]) << expected[i].name;
}

TEST(Catalog, BuiltInEqualsTheFileInTheTree) {
  const auto file = load_catalog_file(METER_SOURCE_DIR "/protocol/catalog/signals.vss.json");
  EXPECT_EQ(file->hash(), default_catalog()->hash());
  EXPECT_EQ(file->text(), default_catalog()->text());
  EXPECT_NE(default_catalog()->source().find("protocol/catalog/signals.vss.json"), std::string::npos);
}

TEST(Catalog, HashCoversTheEntriesNotTheFormatting) {
  EXPECT_EQ(catalog_hash(), catalog_hash());
  EXPECT_NE(catalog_hash(), 0xcbf29ce484222325ULL);  // not the empty FNV basis
  json doc = json::parse(default_catalog()->text());
  // Re-indented, and descriptions changed: same entries, same hash.
  doc["Vehicle"]["children"]["Speed"]["description"] = "another wording";
  auto same = parse_catalog(doc.dump(), "reformatted.json");
  ASSERT_TRUE(same.catalog) << same.error;
  EXPECT_EQ(same.catalog->hash(), default_catalog()->hash());
  doc["Vehicle"]["children"]["Speed"]["max"] = 280;
  auto other = parse_catalog(doc.dump(), "other.json");
  ASSERT_TRUE(other.catalog) << other.error;
  EXPECT_NE(other.catalog->hash(), default_catalog()->hash());
}

TEST(Catalog, AddedLeafIsFoundWithItsIdKindAndRange) {
  const json doc = testing::ev_catalog_json();
  auto r = parse_catalog(doc.dump(2), "ev.vss.json");
  ASSERT_TRUE(r.catalog) << r.error;
  const auto* soc = r.catalog->find(testing::kSocName);
  ASSERT_NE(soc, nullptr);
  EXPECT_EQ(soc->id, 100);
  EXPECT_EQ(soc->kind, SignalKind::Gauge);  // numeric without meter_kind
  EXPECT_EQ(soc->unit, "percent");
  EXPECT_EQ(soc->max, 100.0);
  EXPECT_EQ(r.catalog->size(), default_catalog()->size() + 1);
  EXPECT_EQ(r.catalog->source(), "ev.vss.json");
  EXPECT_EQ(r.catalog->require("Vehicle.Speed", "test").id, sig::kSpeed);
  try {
    r.catalog->require("Vehicle.Nope", "the speedometer");
    ADD_FAILURE() << "require() accepted a missing signal";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "signal catalog ev.vss.json has no signal Vehicle.Nope (needed for the speedometer)");
  }
}

TEST(Catalog, BooleanLeafDefaultsToATelltaleAndStringToText) {
  auto r = parse_catalog(R"({"Cluster": {"type": "branch", "children": {
      "Lamp": {"type": "sensor", "datatype": "boolean", "meter_id": 3},
      "Note": {"type": "attribute", "datatype": "string", "meter_id": 4},
      "Gear": {"type": "actuator", "datatype": "int8", "min": -1, "max": 127, "allowed": [-1, 0, 1, 127],
               "meter_id": 5, "meter_kind": "enum"}}}})",
                         "small.json");
  ASSERT_TRUE(r.catalog) << r.error;
  EXPECT_EQ(r.catalog->find("Cluster.Lamp")->kind, SignalKind::Telltale);
  EXPECT_EQ(r.catalog->find("Cluster.Lamp")->max, 1.0);
  EXPECT_EQ(r.catalog->find("Cluster.Note")->kind, SignalKind::Text);
  EXPECT_EQ(r.catalog->find("Cluster.Gear")->kind, SignalKind::Enum);
}

struct BadCase {
  const char* what;
  std::string text;
  std::string expected;  // the whole message
};

std::string leaf(const std::string& fields) {
  return R"({"Vehicle": {"type": "branch", "children": {"Speed": {"type": "sensor", )" + fields + "}}}}";
}

TEST(CatalogErrors, NameTheFileTheJsonPathAndWhatWasExpected) {
  const std::string ok = R"("datatype": "float", "min": 0, "max": 300, "meter_id": 1)";
  const std::vector<BadCase> cases = {
      {"empty text", "", "c.json:1:1: not valid JSON: parse error at line 1, column 1: syntax error while parsing value - unexpected end of input; expected '[', '{', or a literal"},
      {"syntax error on line 2", "{\"Vehicle\":\n  {,}}", "c.json:2:4: not valid JSON: parse error at line 2, column 4: syntax error while parsing object key - unexpected ','; expected string literal"},
      {"root array", "[]", "c.json: /: expected an object of root branches (\"Vehicle\": {...}), got array"},
      {"empty root", "{}", "c.json: /: expected an object of root branches (\"Vehicle\": {...}), got {}"},
      {"node not an object", R"({"Vehicle": 3})", "c.json: /Vehicle: expected a VSS node (an object), got number"},
      {"no type", R"({"Vehicle": {"children": {}}})", "c.json: /Vehicle: expected a \"type\" field"},
      {"unknown type", R"({"Vehicle": {"type": "struct"}})",
       "c.json: /Vehicle/type: expected \"branch\", \"sensor\", \"actuator\" or \"attribute\", got \"struct\""},
      {"branch without children", R"({"Vehicle": {"type": "branch"}})",
       "c.json: /Vehicle: expected a \"children\" object in a branch"},
      {"children not an object", R"({"Vehicle": {"type": "branch", "children": []}})",
       "c.json: /Vehicle/children: expected an object, got array"},
      {"no leaves", R"({"Vehicle": {"type": "branch", "children": {}}})",
       "c.json: /: expected at least one sensor, actuator or attribute"},
      {"dotted name", R"({"Vehicle": {"type": "branch", "children": {"A.B": {"type": "branch", "children": {}}}}})",
       "c.json: /Vehicle/children/A.B: expected a node name without '.' (the path is built from the tree)"},
      {"duplicate key",
       R"({"Vehicle": {"type": "branch", "children": {"Speed": {"type": "sensor", "datatype": "boolean", "meter_id": 1},
                                                      "Speed": {"type": "sensor", "datatype": "boolean", "meter_id": 2}}}})",
       "c.json: /Vehicle/children/Speed: the key appears twice (a JSON object's keys must be unique)"},
      {"duplicate key inside an array", leaf(ok + R"(, "allowed": [1, {"a": 1, "a": 2}])"),
       "c.json: /Vehicle/children/Speed/allowed/1/a: the key appears twice (a JSON object's keys must be unique)"},
      {"slash in a name", R"({"Vehicle": {"type": "branch", "children": {"a/b~c": 3}}})",
       "c.json: /Vehicle/children/a~1b~0c: expected a VSS node (an object), got number"},
      {"no datatype", leaf(R"("meter_id": 1)"), "c.json: /Vehicle/children/Speed: expected a \"datatype\" field"},
      {"array datatype", leaf(R"("datatype": "float[]", "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed/datatype: expected a scalar VSS datatype (uint8..int64, float, double, boolean, string), got \"float[]\""},
      {"no meter_id", leaf(R"("datatype": "float", "min": 0, "max": 1)"),
       "c.json: /Vehicle/children/Speed: expected a \"meter_id\" field (the signal's wire id, 1..65535)"},
      {"meter_id 0", leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": 0)"),
       "c.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got 0"},
      {"meter_id too big", leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": 65536)"),
       "c.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got 65536"},
      {"meter_id fraction", leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": 1.5)"),
       "c.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got 1.5"},
      {"meter_id string", leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": "1")"),
       "c.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got \"1\""},
      {"duplicate id",
       R"({"Vehicle": {"type": "branch", "children": {"A": {"type": "sensor", "datatype": "boolean", "meter_id": 7},
                                                      "B": {"type": "sensor", "datatype": "boolean", "meter_id": 7}}}})",
       "c.json: /Vehicle/children/B/meter_id: id 7 is already used by Vehicle.A"},
      {"no min", leaf(R"("datatype": "float", "max": 300, "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed: expected a \"min\" field (the lowest value the view is designed for)"},
      {"no max", leaf(R"("datatype": "float", "min": 0, "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed: expected a \"max\" field (the highest value the view is designed for)"},
      {"max a string", leaf(R"("datatype": "float", "min": 0, "max": "300", "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed/max: expected a number, got string"},
      {"max below min", leaf(R"("datatype": "float", "min": 10, "max": 5, "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed/max: expected max >= min (10.0)"},
      {"range outside the datatype", leaf(R"("datatype": "int8", "min": -1, "max": 200, "meter_id": 1)"),
       "c.json: /Vehicle/children/Speed: expected min and max within the int8 range -128.0..127.0"},
      {"unknown kind", leaf(ok + R"(, "meter_kind": "needle")"),
       "c.json: /Vehicle/children/Speed/meter_kind: expected \"gauge\", \"enum\", \"counter\", \"telltale\" or \"text\", got \"needle\""},
      {"text kind on a number", leaf(ok + R"(, "meter_kind": "text")"),
       "c.json: /Vehicle/children/Speed/meter_kind: expected \"text\" exactly for datatype string (got kind \"text\", datatype \"float\")"},
      {"telltale with a range", leaf(ok + R"(, "meter_kind": "telltale")"),
       "c.json: /Vehicle/children/Speed: expected the range 0..1 for a telltale (a lamp is off or on)"},
      {"unit a number", leaf(ok + R"(, "unit": 3)"), "c.json: /Vehicle/children/Speed/unit: expected a string, got number"},
      {"allowed not an array", leaf(ok + R"(, "allowed": 3)"),
       "c.json: /Vehicle/children/Speed/allowed: expected a non-empty array, got 3"},
      {"allowed outside the range", leaf(ok + R"(, "allowed": [0, 400])"),
       "c.json: /Vehicle/children/Speed/allowed/1: expected a value within min..max, got 400"},
      {"allowed an object", leaf(ok + R"(, "allowed": {"a": [[[1]]]})"),
       "c.json: /Vehicle/children/Speed/allowed: expected a non-empty array, got an object"},
      {"allowed empty", leaf(ok + R"(, "allowed": [])"),
       "c.json: /Vehicle/children/Speed/allowed: expected a non-empty array, got []"},
      {"meter_id an array", leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": [[1]])"),
       "c.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got an array"},
      {"allowed of objects", leaf(ok + R"(, "allowed": [{}])"),
       "c.json: /Vehicle/children/Speed/allowed/0: expected a number or a string, got object"},
      {"description not text", leaf(ok + R"(, "description": ["a"])"),
       "c.json: /Vehicle/children/Speed/description: expected a string, got array"},
  };
  for (const auto& c : cases) {
    const auto r = parse_catalog(c.text, "c.json");
    EXPECT_FALSE(r.catalog) << c.what;
    EXPECT_EQ(r.error, c.expected) << c.what;
  }
}

TEST(CatalogErrors, DeepNestingIsAnErrorNotAStackOverflow) {
  std::string text;
  for (int i = 0; i < 5000; ++i) text += R"({"B": {"type": "branch", "children": )";
  text += "{}";
  for (int i = 0; i < 5000; ++i) text += "}}";
  const auto r = parse_catalog(text, "deep.json");
  EXPECT_FALSE(r.catalog);
  EXPECT_NE(r.error.find("expected at most 16 levels of branches"), std::string::npos) << r.error;
}

TEST(CatalogErrors, ADeeplyNestedValueIsReportedByTypeNotDumped) {
  // 200000 levels: a recursive walk or dump of this value would exhaust the stack.
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  const auto r = parse_catalog(leaf(R"("datatype": "float", "min": 0, "max": 1, "meter_id": )" + deep), "deep.json");
  EXPECT_FALSE(r.catalog);
  EXPECT_EQ(r.error, "deep.json: /Vehicle/children/Speed/meter_id: expected an integer 1..65535, got an array");
}

// Found by fuzzing (meter_fuzz_catalog: an uncaught exception): a number too large for a double
// ("max": 301e308) made the JSON library throw its out_of_range, which escaped parse_catalog, whose
// contract is an error result, never an exception (the view parses catalogs it receives).
TEST(CatalogErrors, ANumberTooLargeForADoubleIsAnErrorNamingTheFile) {
  const std::string text = R"({"Vehicle": {"type": "branch", "children": {
      "Speed": {"type": "sensor", "datatype": "float", "min": 0, "max": 301e308, "meter_id": 1}}}})";
  CatalogParseResult r;
  ASSERT_NO_THROW(r = parse_catalog(text, "big.vss.json"));
  EXPECT_EQ(r.catalog, nullptr);
  EXPECT_NE(r.error.find("big.vss.json:2:"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("not valid JSON: number overflow"), std::string::npos) << r.error;
}

TEST(CatalogErrors, EveryTruncationOfTheShippedFileIsAnErrorNotACrash) {
  const std::string& text = default_catalog()->text();
  // Every 7th cut keeps the test under a second; the cuts still land inside every kind of token.
  for (std::size_t n = 0; n < text.size(); n += 7) {
    const auto r = parse_catalog(std::string_view(text).substr(0, n), "cut.json");
    EXPECT_FALSE(r.catalog) << n;
    EXPECT_EQ(r.error.rfind("cut.json:", 0), 0U) << n << ": " << r.error;
  }
}

TEST(CatalogErrors, FilesThatCannotBeReadOrParsedNameTheFile) {
  EXPECT_THROW(
      {
        try {
          load_catalog_file("/nonexistent/x.vss.json");
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "cannot open signal catalog /nonexistent/x.vss.json");
          throw;
        }
      },
      std::runtime_error);
  const std::string path = ::testing::TempDir() + "/bad.vss.json";
  std::ofstream(path) << R"({"Vehicle": {"type": "sensor", "datatype": "float", "min": 0, "max": 1}})";
  try {
    use_catalog_option(path);
    ADD_FAILURE() << "a bad --catalog was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": /Vehicle: expected a \"meter_id\" field (the signal's wire id, 1..65535)");
  }
  EXPECT_EQ(active_catalog(), default_catalog());  // a failed --catalog leaves the default active
}

TEST(Catalog, CatalogOptionMakesTheFileActive) {
  ActiveCatalogGuard guard;
  const std::string path = ::testing::TempDir() + "/one.vss.json";
  std::ofstream(path) << R"({"Cluster": {"type": "branch", "children": {"Lamp": {"type": "sensor", "datatype": "boolean", "meter_id": 42}}}})";
  const auto c = use_catalog_option(path);
  EXPECT_EQ(active_catalog(), c);
  EXPECT_EQ(catalog().size(), 1U);
  EXPECT_EQ(find_signal("Cluster.Lamp")->id, 42);
  EXPECT_EQ(find_signal(sig::kSpeed), nullptr);
  EXPECT_EQ(use_catalog_option(""), c);  // "" keeps what is active
}

TEST(Catalog, StatusAndKindNamesRoundTrip) {
  for (auto s : {SignalStatus::Valid, SignalStatus::TimedOut, SignalStatus::Invalid, SignalStatus::NotAvailable}) {
    EXPECT_EQ(status_from_string(to_string(s)), s);
  }
  EXPECT_FALSE(status_from_string("bogus"));
  for (auto k : {SignalKind::Gauge, SignalKind::Enum, SignalKind::Telltale, SignalKind::Counter, SignalKind::Text}) {
    EXPECT_EQ(kind_from_string(to_string(k)), k);
  }
  EXPECT_FALSE(kind_from_string("lamp"));
}

}  // namespace
}  // namespace meter::protocol
