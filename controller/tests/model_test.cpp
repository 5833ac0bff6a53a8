#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
using meter::protocol::SignalStatus;
namespace sig = meter::protocol::sig;

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

// The model reports which outputs a tick changed, so the run loop publishes exactly those.
TEST(Model, ChangedListsOnlyOutputsWhoseValueOrStatusMoved) {
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping("[Vehicle.Speed]\nsource = Speed.WheelA\n[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = Speed.Gear\n"));
  m.start(0);
  m.update(0);
  EXPECT_EQ(m.changed().size(), m.outputs().size());  // the first tick reports everything
  m.update(10 * ms);
  EXPECT_TRUE(m.changed().empty());  // nothing received, nothing timed out yet
  m.on_frame(frame(256, 15 * ms, {0x10, 0x27, 0, 0, 3, 0, 0, 0}));
  m.update(20 * ms);
  EXPECT_EQ(m.changed().size(), 2u);  // speed and gear both became valid
  m.on_frame(frame(256, 25 * ms, {0x10, 0x27, 0, 0, 4, 0, 0, 0}));
  m.update(30 * ms);
  ASSERT_EQ(m.changed().size(), 1u);  // only the gear moved
  EXPECT_EQ(m.outputs()[m.changed()[0]].id, sig::kCurrentGear);
  EXPECT_DOUBLE_EQ(m.outputs()[m.changed()[0]].value, 4.0);
}

TEST(Model, ChangedMeansWhatTheLinkCarriesSoMinusZeroAfterZeroIsAChange) {
  // The link carries each value's 64 bits and the view's table compares bits, so a tick that turns
  // 0.0 into -0.0 (here through a value map, which keeps the sign of zero) changes what a readout
  // prints ("-0"): the model must report it, or the view keeps the old value while the controller
  // holds the new one.
  Database db = parse_dbc(kDbc, "t.dbc");
  Model m(&db, parse_mapping("[Vehicle.Powertrain.Transmission.CurrentGear]\nsource = Speed.Gear\nmap = 5:-0\n"
                             "timeout = none\n"));
  m.start(0);
  m.on_frame(frame(256, 5 * ms, {0, 0, 0, 0, 0, 0, 0, 0}));  // gear 0
  m.update(10 * ms);
  ASSERT_EQ(m.output(sig::kCurrentGear)->status, SignalStatus::Valid);
  ASSERT_FALSE(std::signbit(m.output(sig::kCurrentGear)->value));
  m.on_frame(frame(256, 15 * ms, {0, 0, 0, 0, 5, 0, 0, 0}));  // gear 5 -> -0
  m.update(20 * ms);
  ASSERT_TRUE(std::signbit(m.output(sig::kCurrentGear)->value));
  ASSERT_EQ(m.changed().size(), 1u);
  EXPECT_EQ(m.outputs()[m.changed()[0]].id, sig::kCurrentGear);
  m.update(30 * ms);
  EXPECT_TRUE(m.changed().empty());  // the same bits again: no change
}
