// Signals at the edges: gauge mapping (view bindings), needle damping against the closed form,
// odometer drift over 1,000,000 km, wrapping distance counters (docs/numerics.md, "Signals").
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "meter/controller/conditioning/needle.hpp"
#include "meter/controller/conditioning/odometer.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/vocabulary.hpp"
#include "odometer_drive.hpp"

using namespace meter;
using namespace meter::controller;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A scene with one node and one animation "Needle"; the config maps Vehicle.Speed [0, 260] to
// animation time [0, 10] (optionally with a failsafe value).
engine::Scene needle_scene(bool failsafe) {
  engine::Scene s;
  s.nodes.resize(1);
  s.nodes[0].name = "N";
  s.roots = {0};
  engine::Animation a;
  a.name = "Needle";
  s.animations.push_back(a);
  std::string cfg = R"({"format": "meter-scene-config/1", "bindings": [
    {"signal": "Vehicle.Speed", "kind": "animation", "animation": "Needle", "input": [0, 260], "time": [0, 10])";
  cfg += failsafe ? R"(, "failsafe": {"value": 0}}]})" : "}]}";
  s.config = meter::config::parse_scene_config(cfg, "numerics");
  return s;
}

struct Gauge {
  engine::Scene scene;
  engine::BindingEvaluator eval;
  protocol::SignalTable signals;
  explicit Gauge(bool failsafe) : scene(needle_scene(failsafe)), eval(scene) {}
  double time_for(double value, protocol::SignalStatus st = protocol::SignalStatus::Valid) {
    signals.set(protocol::sig::kSpeed, {value, st, ""});
    eval.update(signals, true, -1.0);
    return eval.outputs().animation_time[0];
  }
};

// Closed form of the critically damped needle from rest at x0 toward u: x(t) = u + (x0 - u)(1 + wt)e^{-wt}.
double closed_form(double x0, double u, double w, double t) { return u + (x0 - u) * (1 + w * t) * std::exp(-w * t); }

}  // namespace

// Bound: exact equality at and beyond the ends (time 0 / 10), max error 1e-12 s inside.
TEST(GaugeMapping, BelowAboveExactEndsNanAndInfinity) {
  Gauge g(false);
  EXPECT_EQ(g.time_for(0.0), 0.0);
  EXPECT_EQ(g.time_for(260.0), 10.0);
  EXPECT_EQ(g.time_for(-50.0), 0.0);
  EXPECT_EQ(g.time_for(-1e308), 0.0);
  EXPECT_EQ(g.time_for(400.0), 10.0);
  EXPECT_EQ(g.time_for(1e308), 10.0);
  EXPECT_EQ(g.time_for(std::numeric_limits<double>::denorm_min()), 0.0 + 10.0 * (std::numeric_limits<double>::denorm_min() / 260.0));
  EXPECT_NEAR(g.time_for(130.0), 5.0, 1e-12);
  // Without a failsafe value, NaN and +-Inf hold the last drawn value (never NaN, never an end stop).
  g.time_for(100.0);
  const double held = g.eval.outputs().animation_time[0];
  for (double bad : {std::nan(""), kInf, -kInf}) {
    const double t = g.time_for(bad);
    EXPECT_EQ(t, held) << bad;
    EXPECT_TRUE(g.eval.states()[0].failsafe);
  }
  // With a failsafe value: NaN / Inf show the failsafe (0 -> time 0), exactly.
  Gauge f(true);
  f.time_for(200.0);
  for (double bad : {std::nan(""), kInf, -kInf}) EXPECT_EQ(f.time_for(bad), 0.0) << bad;
  EXPECT_EQ(f.time_for(130.0, protocol::SignalStatus::Invalid), 0.0);
  EXPECT_NEAR(f.time_for(130.0), 5.0, 1e-12);
}

// dt = 0: bit-identical state; dt = 1 ms steps vs closed form: max error 1e-9 of the span over
// 5 s; dt = 10 min: exactly on target with zero velocity.
TEST(Needle, DtZeroOneMillisecondAndTenMinutesAgainstClosedForm) {
  const double tau = 0.2, w = 1 / tau;
  NeedleFilter n(tau);
  n.reset(20.0);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(n.step(120.0, 0.0), 20.0);
  EXPECT_EQ(n.velocity(), 0.0);
  double max_err = 0;
  for (int i = 1; i <= 5000; ++i) {
    const double x = n.step(120.0, 0.001);
    max_err = std::max(max_err, std::abs(x - closed_form(20.0, 120.0, w, i * 0.001)));
    ASSERT_LE(x, 120.0);  // no overshoot
  }
  EXPECT_LT(max_err, 1e-9 * 100.0);
  NeedleFilter m(tau);
  m.reset(20.0);
  m.step(120.0, 0.3);
  EXPECT_EQ(m.step(120.0, 600.0), 120.0);
  EXPECT_EQ(m.velocity(), 0.0);
  // Irregular dt (0..50 ms, the jitter of a loaded box): still the closed form within 1e-9 * span.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> dt(0.0, 0.05);
  NeedleFilter j(tau);
  j.reset(0.0);
  double t = 0;
  while (t < 3.0) {
    const double d = dt(rng);
    t += d;
    j.step(-80.0, d);
  }
  EXPECT_NEAR(j.value(), closed_form(0.0, -80.0, w, t), 1e-9 * 80.0);
}

// Extreme stiffness: tau from 1e-300 s to 1e-6 s: one 1 ms step lands exactly on the target, all
// state finite; a very soft needle (tau = 1e6 s) moves by the closed form (relative 1e-12).
TEST(Needle, ExtremeStiffnessStaysFiniteAndExact) {
  for (double tau : {1e-300, 1e-100, 1e-9, 1e-6}) {
    NeedleFilter n(tau);
    n.reset(0.0);
    EXPECT_EQ(n.step(250.0, 0.001), 250.0) << tau;
    EXPECT_TRUE(std::isfinite(n.velocity())) << tau;
    EXPECT_EQ(n.step(-1e300, 0.001), -1e300) << tau;
    const double x = n.step(1e300, std::numeric_limits<double>::denorm_min());  // w * e0 overflows
    EXPECT_TRUE(std::isfinite(x)) << tau;
    EXPECT_TRUE(std::isfinite(n.value()) && std::isfinite(n.velocity())) << tau;
  }
  NeedleFilter soft(1e6);
  soft.reset(0.0);
  soft.step(100.0, 10.0);
  EXPECT_NEAR(soft.value(), closed_form(0.0, 100.0, 1e-6, 10.0), 1e-12 * 100.0);
}

// No overshoot: across 20,000 random target changes while moving, the needle never crosses the
// target it is heading for (sign of x - target never flips during a hold).
TEST(Needle, NeverCrossesTheTargetUnderRandomRetargeting) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> tgt(0, 260), hold(0.001, 0.4), dt(0.0005, 0.02);
  NeedleFilter n(0.15);
  n.reset(0);
  for (int k = 0; k < 20000; ++k) {
    const double target = tgt(rng), until = hold(rng);
    const double side = n.value() - target;
    for (double t = 0; t < until;) {
      const double d = dt(rng);
      t += d;
      const double x = n.step(target, d);
      ASSERT_TRUE(std::isfinite(x));
      ASSERT_GE((x - target) * side, 0.0) << "crossed target " << target << " at change " << k;
    }
  }
}


// Unit variant of odometer_slow_test.cpp (3.6e6 steps = 10,000 km at ~1000 km/h): the integer odometer equals the exact floor of the true distance (drift < 1 um, the
// proportional bound of "1 m per 1,000,000 km" would be 1 cm).
TEST(Odometer, TenThousandKmIn10msStepsHasNoDrift) {
  const auto r = numerics::drive(3'600'000, 100'000);
  EXPECT_EQ(r.odo_um, r.exact_um);
  EXPECT_NEAR(static_cast<double>(r.exact_um) / 1e9, 10'000.0, 1.0);
  std::printf("10,000 km: integer odometer error %lld um; naive double-km accumulator error %.3f m\n",
              static_cast<long long>(r.odo_um - r.exact_um), (r.naive_km - static_cast<double>(r.exact_um) / 1e9) * 1000.0);
}

// Wrapping counters: 8-, 16-, 32- and 64-bit counters wrapping many times; total within 1 um of the
// exact count * um_per_count (carry of the fraction); a bad scale (NaN, negative, Inf) adds nothing.
TEST(Odometer, CounterWrapAroundIsExact) {
  std::mt19937_64 rng(17);
  for (unsigned bits : {8u, 16u, 32u, 64u}) {
    const std::uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    const std::uint64_t max_step = std::min<std::uint64_t>(mask, 200);
    Odometer o;
    std::uint64_t c = mask - 5;  // start just below the wrap
    o.add_counter(c, bits, 1234.5678);
    std::uint64_t counted = 0;
    for (int i = 0; i < 100000; ++i) {
      const std::uint64_t step = rng() % (max_step + 1);
      c = (c + step) & mask;
      counted += step;
      o.add_counter(c, bits, 1234.5678);
    }
    const double exact = static_cast<double>(counted) * 1234.5678;
    EXPECT_LE(std::abs(static_cast<double>(o.total_um()) - exact), 1.0) << bits;
  }
  for (double bad : {std::nan(""), -1.0, kInf}) {
    Odometer o;
    o.add_counter(10, 16, bad);
    o.add_counter(20, 16, bad);
    EXPECT_EQ(o.total_um(), 0) << bad;
    o.add_counter(30, 16, 1.0);  // the latch still moved: only the 10 new counts
    EXPECT_EQ(o.total_um(), 10) << bad;
  }
}
