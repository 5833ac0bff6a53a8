#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "meter/controller/mapping.hpp"
#include "meter/controller/model.hpp"

using namespace meter::controller;
using meter::protocol::SignalStatus;
namespace sig = meter::protocol::sig;

namespace {
const char* kDbc =
    "BO_ 256 Speed: 8 ECU\n"
    " SG_ WheelA : 0|16@1+ (0.01,0) [0|100] \"m/s\" ICL\n"
    " SG_ WheelB : 16|16@1+ (0.01,0) [0|100] \"m/s\" ICL\n"
    " SG_ Gear : 32|4@1+ (1,0) [0|6] \"\" ICL\n"
    " SG_ Left : 36|1@1+ (1,0) [0|1] \"\" ICL\n"
    "BO_ 512 Temps: 8 ECU\n"
    " SG_ Coolant : 0|32@1- (1,0) [0|0] \"C\" ICL\n"
    " SG_ Outside : 32|8@1+ (1,-40) [-40|80] \"C\" ICL\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 256 20;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 512 100;\n"
    "SIG_VALTYPE_ 512 Coolant : 1;\n";

constexpr std::int64_t ms = 1000000;

CanFrame frame(std::uint32_t id, std::int64_t t, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  f.timestamp_ns = t;
  f.len = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}
}  // namespace

TEST(Mapping, ErrorsNameLineAndExpectation) {
  auto expect_error = [](const std::string& text, int line, const std::string& what) {
    try {
      parse_mapping(text, "m.map");
      ADD_FAILURE() << "no error for " << text;
    } catch (const MappingError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("m.map:" + std::to_string(line)), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("[Vehicle.Nope]\n", 1, "catalog signal name");
  expect_error("[Vehicle.Speed]\nsource = A\n", 2, "Message.Signal");
  expect_error("[Vehicle.Speed]\nsource = A.B\nneedle = fast\n", 3, "number");
  expect_error("[Vehicle.Speed]\nsource = A.B\nspeedometer = 1.5 0\n", 3, "R39");
  expect_error("[Vehicle.Speed]\nsource = A.B\nbogus = 1\n", 3, "unknown key");
  expect_error("[global]\nbulb_check = 5s\n", 2, "2..4");
  expect_error("[Vehicle.Speed]\n", 1, "source");
  expect_error("source = A.B\n", 1, "outside any");
  expect_error("[Vehicle.Speed]\nsource = modbus.x\n", 1, "modbus.register");
  expect_error("[Cluster.Telltale.FuelLow]\nrule = below Vehicle.Foo 10 12\n", 2, "not a catalog signal");
  expect_error("[Cluster.Telltale.SeatBelt]\nsource = A.B\nrule = seatbelt\nfirst_level = 3\n", 4, "4..8");
  expect_error("[Vehicle.Speed]\nsource = A.B\nconvert = furlong->km/h\n", 3, "m/s->km/h");
  Database db = parse_dbc(kDbc, "t.dbc");
  try {
    Model m(&db, parse_mapping("\n[Vehicle.Speed]\nsource = Speed.Nope\n", "m.map"));
    ADD_FAILURE();
  } catch (const MappingError& e) {
    EXPECT_NE(std::string(e.what()).find("m.map:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no signal 'Nope'"), std::string::npos) << e.what();
  }
}

TEST(Model, MeanConversionAndAutoTimeouts) {
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping("[Vehicle.Speed]\nsource = Speed.WheelA, Speed.WheelB\ncombine = mean\nconvert = m/s->km/h\n"));
  m.start(0);
  m.update(10 * ms);
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::NotAvailable);
  m.update(999 * ms);
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::NotAvailable);  // first timeout: max(1 s, 10 cycles)
  m.update(1001 * ms);
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::TimedOut);
  m.on_frame(frame(256, 1010 * ms, {0xE8, 0x03, 0xD0, 0x07, 0, 0, 0, 0}));  // 10 and 20 m/s
  m.update(1020 * ms);
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::Valid);
  EXPECT_NEAR(m.output(sig::kSpeed)->value, 54.0, 1e-9);  // mean 15 m/s
  m.update(1010 * ms + 60 * ms);  // exactly 3 cycles: still fine
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::Valid);
  m.update(1010 * ms + 61 * ms);  // later timeout: 3 x 20 ms
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::TimedOut);
  EXPECT_NEAR(m.output(sig::kSpeed)->value, 54.0, 1e-9);  // last value kept for the failsafe look
}

TEST(Model, TimeoutActionsRangeRemapAndBadValues) {
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping("[Vehicle.Exterior.AirTemperature]\nsource = Temps.Outside\non_timeout = hold\n"
                             "[Vehicle.Powertrain.CombustionEngine.ECT]\nsource = Temps.Coolant\non_timeout = substitute -40\n"
                             "[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = Speed.Gear\nmap = 7:0\n"
                             "out_of_range = accept\ntimeout = none\n"));
  m.start(0);
  // Coolant float32 90.5, outside 60 -> 20 C.
  m.on_frame(frame(512, 5 * ms, {0x00, 0x00, 0xB5, 0x42, 60, 0, 0, 0}));
  m.on_frame(frame(256, 5 * ms, {0, 0, 0, 0, 7, 0, 0, 0}));  // gear 7 (beyond [0|6])
  m.update(10 * ms);
  EXPECT_EQ(m.output(sig::kOutsideTemp)->value, 20.0);
  EXPECT_EQ(m.output(sig::kCoolantTemp)->value, 90.5);
  EXPECT_EQ(m.output(sig::kCurrentGear)->value, 0.0);  // 7 accepted and remapped to neutral
  EXPECT_EQ(m.output(sig::kCurrentGear)->status, SignalStatus::Valid);
  m.update(400 * ms);  // both 100 ms messages timed out
  EXPECT_EQ(m.output(sig::kOutsideTemp)->status, SignalStatus::Valid);  // hold
  EXPECT_EQ(m.output(sig::kOutsideTemp)->value, 20.0);
  EXPECT_EQ(m.output(sig::kCoolantTemp)->status, SignalStatus::Valid);  // substitute
  EXPECT_EQ(m.output(sig::kCoolantTemp)->value, -40.0);
  EXPECT_EQ(m.output(sig::kCurrentGear)->status, SignalStatus::Valid);  // timeout = none
  // NaN in the float signal: invalid, and 0 instead of a NaN; out of range outside temp: invalid.
  m.on_frame(frame(512, 401 * ms, {0x00, 0x00, 0xC0, 0x7F, 250, 0, 0, 0}));
  m.update(402 * ms);
  EXPECT_EQ(m.output(sig::kCoolantTemp)->status, SignalStatus::Invalid);
  EXPECT_EQ(m.output(sig::kCoolantTemp)->value, 0.0);
  EXPECT_EQ(m.output(sig::kOutsideTemp)->status, SignalStatus::Invalid);
  // Short frame: the signals it does not cover are invalid.
  m.on_frame(frame(512, 403 * ms, {0x00, 0x00, 0xB5, 0x42}));
  m.update(404 * ms);
  EXPECT_EQ(m.output(sig::kCoolantTemp)->status, SignalStatus::Valid);
  EXPECT_EQ(m.output(sig::kOutsideTemp)->status, SignalStatus::Invalid);
}

TEST(Model, BulbCheckBlinkAndIgnitionRestart) {
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping("[global]\nbulb_check = 2s\n[Cluster.Telltale.TurnLeft]\nsource = Speed.Left\nblink = 0.5 0.5\n"
                             "[Cluster.Telltale.ABS]\nsource = Speed.Gear\ntimeout = none\n"));
  m.start(0);
  m.update(1 * ms);
  EXPECT_EQ(m.output(sig::kTurnLeft)->value, 1.0);  // bulb check lights even unmapped-yet lamps
  EXPECT_EQ(m.output(sig::kAbs)->value, 1.0);
  m.update(1999 * ms);
  EXPECT_EQ(m.output(sig::kAbs)->value, 1.0);
  m.update(2000 * ms);
  EXPECT_EQ(m.output(sig::kAbs)->value, 0.0);
  EXPECT_EQ(m.output(sig::kAbs)->status, SignalStatus::NotAvailable);
  // Indicator requested at 3.0 s: lit for 250 ms, dark for 250 ms, ...
  for (std::int64_t t = 3000; t <= 4000; t += 10) {
    m.on_frame(frame(256, t * ms, {0, 0, 0, 0, 0x10, 0, 0, 0}));
    m.update(t * ms);
    bool expect = ((t - 3000) % 500) < 250;
    ASSERT_EQ(m.output(sig::kTurnLeft)->value, expect ? 1.0 : 0.0) << t;
  }
}

TEST(Model, OdometerFromSpeedPersistsAndReloads) {
  Database db = parse_dbc(kDbc, "t.dbc");
  auto dir = std::filesystem::temp_directory_path() / ("meter-model-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const std::string map = "[global]\npersist_interval = 1s\n[Vehicle.Speed]\nsource = Speed.WheelA\nconvert = m/s->km/h\n"
                          "[Vehicle.TraveledDistance]\naccumulate = speed\n";
  {
    Model m(&db, parse_mapping(map), ModelOptions{dir.string()});
    m.start(0);
    // 25 m/s = 90 km/h for 10 s in 10 ms ticks = 250 m.
    for (std::int64_t t = 0; t <= 10000; t += 10) {
      m.on_frame(frame(256, t * ms, {0xC4, 0x09, 0, 0, 0, 0, 0, 0}));
      m.update(t * ms);
    }
    EXPECT_EQ(m.odometer().total_um(), 250LL * 1000000);
    EXPECT_NEAR(m.output(sig::kOdometer)->value, 0.2, 1e-12);  // whole tenths, never rounded up
    EXPECT_NEAR(m.output(sig::kTrip)->value, 0.2, 1e-12);
    EXPECT_GE(m.stats().persist_saves, 9u);
  }
  Model again(&db, parse_mapping(map), ModelOptions{dir.string()});
  EXPECT_GE(again.odometer().total_um(), 240LL * 1000000);  // at most one interval (1 s = 25 m) lost
  std::filesystem::remove_all(dir);
}

#include <fstream>
#include <iterator>
#include <random>

TEST(Mapping, MutatedDemoMapNeverCrashes) {
  std::ifstream in(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.map", std::ios::binary);
  std::string base((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(base.empty());
  Database db = load_dbc(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.dbc");
  std::mt19937 rng(11);
  const char alphabet[] = "0123456789.-e=[]#, abcmsMS\n";
  int ok = 0, errors = 0;
  for (int i = 0; i < 1500; ++i) {
    std::string t = base;
    for (int k = 0; k < 1 + static_cast<int>(rng() % 4); ++k) t[rng() % t.size()] = alphabet[rng() % (sizeof alphabet - 1)];
    try {
      Model m(&db, parse_mapping(t, "fuzz.map"));
      m.start(0);
      m.update(1000000);
      ++ok;
    } catch (const MappingError& e) {
      EXPECT_NE(std::string(e.what()).find("fuzz.map:"), std::string::npos) << e.what();
      ++errors;
    } catch (const std::invalid_argument&) {
      ++errors;  // conditioning limits (needle tau, bulb check) checked again by the classes
    }
  }
  EXPECT_GT(ok, 0);
  EXPECT_GT(errors, 0);
}
