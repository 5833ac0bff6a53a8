#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "meter/controller/conditioning/fuel.hpp"
#include "meter/controller/conditioning/needle.hpp"
#include "meter/controller/conditioning/odometer.hpp"
#include "meter/controller/conditioning/telltales.hpp"

using namespace meter::controller;

TEST(Needle, StepFromRestNeverOvershootsAndIsExactForAnyDt) {
  // One big step and many small steps reach the same state: the closed form is exact.
  NeedleFilter a(0.2), b(0.2);
  a.reset(0);
  b.reset(0);
  a.step(100, 0.5);
  for (int i = 0; i < 500; ++i) b.step(100, 0.001);
  EXPECT_NEAR(a.value(), b.value(), 1e-9);
  EXPECT_NEAR(a.velocity(), b.velocity(), 1e-9);
  // Analytic: x = u (1 - (1 + w t) e^{-w t}), w = 5, t = 0.5.
  EXPECT_NEAR(a.value(), 100 * (1 - (1 + 2.5) * std::exp(-2.5)), 1e-9);
  NeedleFilter c(0.2);
  c.reset(0);
  double prev = 0;
  for (int i = 0; i < 5000; ++i) {
    double x = c.step(100, 0.001);
    ASSERT_LE(x, 100.0);
    ASSERT_GE(x, prev);  // monotone approach
    prev = x;
  }
}

TEST(Needle, ZeroHugeAndGarbageDt) {
  NeedleFilter n(0.1);
  n.reset(10);
  EXPECT_EQ(n.step(50, 0.0), 10.0);                       // dt = 0: nothing moves
  EXPECT_EQ(n.step(50, -1.0), 10.0);                      // negative dt ignored
  EXPECT_EQ(n.step(50, std::nan("")), 10.0);
  EXPECT_EQ(n.step(std::nan(""), 0.1), 10.0);             // NaN target ignored
  EXPECT_EQ(n.step(50, 600.0), 50.0);                     // a 10-minute stall: exactly there
  EXPECT_TRUE(std::isfinite(n.velocity()));
  EXPECT_EQ(n.step(-20, 1e300), -20.0);
  EXPECT_THROW(NeedleFilter(0.0), std::invalid_argument);
}

TEST(Needle, TargetChangeWhileMovingDoesNotSwingPast) {
  NeedleFilter n(0.3);
  n.reset(0);
  for (int i = 0; i < 300; ++i) n.step(200, 0.001);  // moving fast upward
  ASSERT_GT(n.velocity(), 0);
  const double target = n.value() + 1.0;  // new target just ahead of the needle
  for (int i = 0; i < 3000; ++i) ASSERT_LE(n.step(target, 0.001), target);
}

TEST(SpeedometerR39, AlwaysInsideTheLegalBand) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> v(0, 300), lag(-30, 30);
  SpeedometerRule r{1.05, 3.0};
  for (int i = 0; i < 100000; ++i) {
    double truth = v(rng);
    double shown = r.apply(truth + lag(rng), truth);
    ASSERT_TRUE(SpeedometerRule::legal(shown, truth)) << truth << " " << shown;
  }
  EXPECT_DOUBLE_EQ(r.apply(100, 100), 108.0);
  EXPECT_DOUBLE_EQ(r.apply(0, 0), 3.0);
  const SpeedometerRule max_rule{1.1, 4};
  EXPECT_DOUBLE_EQ(max_rule.apply(200, 200), 224.0);  // clamped at 10 % + 4
  EXPECT_EQ(r.apply(std::nan(""), 50), 55.5);
}

TEST(Fuel, SloshFilteredRefuelDetectedSenderFault) {
  FuelFilter f;
  f.step(50, true, 0, 0.1);
  EXPECT_EQ(f.value(), 50);
  // Driving: +-10 % slosh around 50 barely moves the gauge.
  for (int i = 0; i < 600; ++i) f.step(50 + 10 * std::sin(i * 0.7), true, 80, 0.1);
  EXPECT_NEAR(f.value(), 50, 1.0);
  // Stopped and refuelled to 90: goes there after the confirmation time, not before.
  for (int i = 0; i < 10; ++i) f.step(90, true, 0, 0.1);
  EXPECT_LT(f.value(), 70);
  for (int i = 0; i < 15; ++i) f.step(90, true, 0, 0.1);
  EXPECT_EQ(f.value(), 90);
  EXPECT_EQ(f.refuels(), 1);
  // Rising while driving is slosh, not a refuel.
  for (int i = 0; i < 50; ++i) f.step(99, true, 60, 0.1);
  EXPECT_EQ(f.refuels(), 1);
  // Sender fault: implausible value for longer than the fault time.
  for (int i = 0; i < 20; ++i) f.step(250, true, 60, 0.1);
  EXPECT_FALSE(f.fault());
  for (int i = 0; i < 20; ++i) f.step(250, true, 60, 0.1);
  EXPECT_TRUE(f.fault());
  f.step(40, true, 60, 0.1);  // sender back: shows the truth at once
  EXPECT_FALSE(f.fault());
  EXPECT_EQ(f.value(), 40);
}

TEST(Odometer, IntegerMicrometresDoNotDrift) {
  Odometer o;
  // 100 km/h for 1 hour in 1 ms steps = exactly 100 km.
  for (int i = 0; i < 3600 * 1000; ++i) o.add_speed(100.0, 1000000);
  EXPECT_EQ(o.total_um(), 100LL * 1000 * 1000 * 1000);
  // At a large total, tiny steps still count (a double km counter would lose them).
  Odometer big;
  big.set(999999LL * 1000000000LL, 0);
  for (int i = 0; i < 1000; ++i) big.add_speed(3.6, 1000000);  // 1 mm per step
  EXPECT_EQ(big.total_um() - 999999LL * 1000000000LL, 1000 * 1000);
  o.add_speed(std::nan(""), 1000);
  o.add_speed(-5, 1000);
  o.add_speed(50, -1000);
  EXPECT_EQ(o.total_um(), 100LL * 1000 * 1000 * 1000);
  Odometer c;
  c.add_counter(250, 8, 200000);  // latches only
  c.add_counter(4, 8, 200000);    // wrapped: 10 counts
  EXPECT_EQ(c.total_um(), 10 * 200000);
}

TEST(Telltales, BlinkBulbCheckSeatBeltHysteresis) {
  BlinkPattern b{0.5, 0.5};
  EXPECT_TRUE(b.lit(0, 0));
  EXPECT_TRUE(b.lit(249999999, 0));
  EXPECT_FALSE(b.lit(250000000, 0));
  EXPECT_TRUE(b.lit(500000000, 0));
  EXPECT_FALSE(b.lit(-1, 0));
  EXPECT_THROW(BulbCheck(1.5), std::invalid_argument);
  EXPECT_THROW(BulbCheck(4.5), std::invalid_argument);
  BulbCheck bc(2.5);
  EXPECT_FALSE(bc.active(0));
  bc.start(1000);
  EXPECT_TRUE(bc.active(1000));
  EXPECT_TRUE(bc.active(1000 + 2499999999LL));
  EXPECT_FALSE(bc.active(1000 + 2500000000LL));
  EXPECT_THROW(SeatBeltReminder(SeatBeltConfig{3.0}), std::invalid_argument);
  SeatBeltReminder s(SeatBeltConfig{5.0});
  EXPECT_FALSE(s.lit(0, true, 0));  // ignition off
  s.ignition_on(0);
  EXPECT_TRUE(s.lit(1000000000, true, 0));    // first level
  EXPECT_FALSE(s.lit(1000000000, false, 0));  // buckled
  EXPECT_FALSE(s.lit(6000000000, true, 0));   // first level over, standing
  EXPECT_TRUE(s.lit(6000000000, true, 15));   // moving unbuckled
  EXPECT_TRUE(s.lit(7000000000, true, 50));   // second level starts lit...
  EXPECT_FALSE(s.lit(7600000000, true, 50));  // ...and flashes at 1 Hz
  Hysteresis h{10, 12, true};
  EXPECT_FALSE(h.update(11));
  EXPECT_TRUE(h.update(9.9));
  EXPECT_TRUE(h.update(11.5));
  EXPECT_FALSE(h.update(12.1));
}
