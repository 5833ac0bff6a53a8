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

// UN ECE R39 (5.3), in its own words: the speed indicated (V1) shall not be less than the true
// speed (V2), and 0 <= V1 - V2 <= 0.1 V2 + 4 km/h. The band is computed here from those words on
// exact hundredths of a km/h, not by the product's arithmetic (SpeedometerRule::apply / legal).
namespace {
struct R39Band {
  double low, high;
};
R39Band r39_band(int true_centi_kmh) {
  // t = V2 in hundredths of a km/h; V2 + V2 / 10 + 4 km/h in thousandths is 10 t + t + 4000.
  const long long v2 = true_centi_kmh;
  return {static_cast<double>(v2) / 100.0, static_cast<double>(v2 * 10 + v2 + 4000) / 1000.0};
}
bool within_r39(const R39Band& b, double shown) { return shown >= b.low - 1e-9 && shown <= b.high + 1e-9; }
}  // namespace

TEST(SpeedometerR39, AlwaysInsideTheRegulationsBand) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> v_centi(0, 30000);  // 0..300 km/h
  std::uniform_real_distribution<double> lag(-60, 60);   // the damped needle behind or ahead
  for (const SpeedometerRule& r : {SpeedometerRule{1.05, 3.0}, SpeedometerRule{1.02, 1.0}, SpeedometerRule{1.0, 0.0},
                                   SpeedometerRule{1.3, 10.0}, SpeedometerRule{0.9, 0.0}}) {
    for (int i = 0; i < 20000; ++i) {
      const int t = v_centi(rng);
      const double truth = t / 100.0;
      const R39Band band = r39_band(t);
      const double shown = r.apply(truth + lag(rng), truth);
      ASSERT_TRUE(within_r39(band, shown)) << "rule " << r.ratio << " x + " << r.offset_kmh << ": true " << truth
                                           << " km/h shown " << shown << ", R39 allows " << band.low << ".." << band.high;
    }
  }
}

// The band's edges are where R39 puts them, and a reading already inside it is left alone.
TEST(SpeedometerR39, BandEdgesAndLegalReadingsFromTheRegulation) {
  const SpeedometerRule none{1.0, 0.0};
  for (int t = 0; t <= 30000; t += 250) {
    const R39Band band = r39_band(t);
    const double truth = t / 100.0;
    EXPECT_NEAR(none.apply(truth - 50.0, truth), band.low, 1e-9) << truth;   // reads low: raised to V2
    EXPECT_NEAR(none.apply(truth + 500.0, truth), band.high, 1e-9) << truth; // reads high: 110 % + 4
    EXPECT_NEAR(none.apply(truth, truth), truth, 1e-9) << truth;             // exact: legal, unchanged
  }
  EXPECT_DOUBLE_EQ(r39_band(0).high, 4.0);        // standing: up to 4 km/h
  EXPECT_DOUBLE_EQ(r39_band(10000).high, 114.0);  // 100 km/h: up to 114
  EXPECT_DOUBLE_EQ(r39_band(20000).high, 224.0);  // 200 km/h: up to 224
  // A settled needle (displayed = true) with the designed-in over-read 1.05 x + 3 reads it exactly.
  const SpeedometerRule over{1.05, 3.0};
  EXPECT_NEAR(over.apply(100, 100), 108.0, 1e-9);
  EXPECT_NEAR(over.apply(0, 0), 3.0, 1e-9);
  EXPECT_NEAR((SpeedometerRule{1.1, 4}.apply(200, 200)), 224.0, 1e-9);
  EXPECT_NEAR((SpeedometerRule{1.2, 4}.apply(200, 200)), 224.0, 1e-9);  // over the band: 110 % + 4
  EXPECT_NEAR(over.apply(std::nan(""), 50), 55.5, 1e-9);               // no needle value: from V2
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
