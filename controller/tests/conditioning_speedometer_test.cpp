// The speedometer chain as the cluster runs it (OutputConditioner: needle damping, then the UN R39
// band) on noisy speed samples: ramps and steady speeds with +-3 km/h of sensor noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>

#include "meter/controller/conditioning/output_conditioner.hpp"
#include "meter/controller/mapping/mapping.hpp"

using namespace meter::controller;
using meter::protocol::SignalStatus;

namespace {

constexpr double kDt = 0.01;  // the model's 10 ms tick, one speed sample per tick

struct DriveResult {
  double max_step = 0;      // largest tick-to-tick change of the shown value (after the first second)
  double worst_low = 0;     // most the shown value fell below the noise-free speed
  double worst_high = -1e9; // most the shown value exceeded 110 % + 4 km/h of the noise-free speed
  int band_violations = 0;  // ticks outside the band around the conditioner's own speed estimate
  double sd = 0;            // standard deviation of the shown value after the first 2 s
};

// Drives the demo vehicle's speedometer (needle 0.15 s, 1.02 x + 1 km/h over-read) for 'seconds'
// with the noise-free speed profile 'truth' plus 'noise'.
DriveResult drive(double seconds, const std::function<double(double)>& truth, const std::function<double(int)>& noise) {
  Mapping map = parse_mapping("[Vehicle.Speed]\nsource = Speed.VehicleSpeed\nneedle = 0.15\nspeedometer = 1.02 1.0\n");
  OutputConditioner c(map.outputs[0], meter::protocol::SignalKind::Gauge);
  DriveResult r;
  double prev = 0, sum = 0, sum2 = 0;
  int n = 0;
  const int ticks = static_cast<int>(seconds / kDt);
  for (int k = 0; k < ticks; ++k) {
    const double t = k * kDt;
    const double g = truth(t);
    const double sample = std::max(0.0, g + noise(k));
    const OutputValue shown = c.condition({sample, SignalStatus::Valid}, static_cast<std::int64_t>(t * 1e9), k ? kDt : 0.0, sample);
    EXPECT_EQ(shown.status, SignalStatus::Valid);
    if (t >= 1.0) r.max_step = std::max(r.max_step, std::fabs(shown.value - prev));
    if (t >= 1.0) {
      r.worst_low = std::max(r.worst_low, g - shown.value);
      r.worst_high = std::max(r.worst_high, shown.value - (1.1 * g + 4.0));
    }
    // R39's band around the estimate, in the regulation's words (not SpeedometerRule::legal's arithmetic).
    if (const auto est = c.speed_estimate(); !est || shown.value < *est - 1e-9 || shown.value - *est > *est / 10 + 4 + 1e-9)
      ++r.band_violations;
    if (t >= 2.0) {
      sum += shown.value;
      sum2 += shown.value * shown.value;
      ++n;
    }
    prev = shown.value;
  }
  r.sd = n > 1 ? std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n))) : 0.0;
  return r;
}

std::function<double(int)> uniform_noise(unsigned seed) {
  auto rng = std::make_shared<std::mt19937>(seed);
  return [rng](int) { return std::uniform_real_distribution<double>(-3.0, 3.0)(*rng); };
}
// The worst case for a clamp around the raw sample: the noise swings the full 6 km/h every tick.
double alternating_noise(int k) { return k % 2 ? 3.0 : -3.0; }

// Jitter bound: the raw samples jump by up to 6 km/h from one tick to the next. The speed estimate
// the band is held against moves by at most its level gain 1 - exp(-dt / 0.2 s) = 0.049 of such a
// swing (0.29 km/h) plus its trend term (time constant 0.5 s, a further ~0.05 km/h); the band's upper
// edge scales that by 1.1, and a 10 km/h/s ramp adds 0.11 km/h per tick. So a calm speedometer moves
// by less than 0.6 km/h per 10 ms tick (measured: 0.28 at most); 1 km/h is the bound, against the 6
// km/h a band clamped around the raw sample passes through (measured on the old chain: 5.4).
constexpr double kMaxStepKmh = 1.0;
// How far the shown value may sit below the noise-free speed (or above its 110 % + 4 km/h): the
// estimate's error. What is left of the uniform +-3 km/h noise after the level filter has a standard
// deviation of about 0.35 km/h; at the onset of a 10 km/h/s ramp the trend needs about its time
// constant to pick the slope up, a lag of up to ~0.8 km/h. Together 1.5 km/h (measured: 1.11 at most
// over 20 noise seeds), against the 3 km/h of the raw sample.
constexpr double kEstimateErrorKmh = 1.5;
// Steady speed: the needle (critically damped, w = 1 / 0.15 s) passes white noise with a variance
// gain of dt * w / 4 = 0.017, so the uniform +-3 km/h noise (sd 1.73 km/h) leaves sd 0.22 km/h on the
// needle, 0.23 after the 1.02 over-read; alternating noise sits at the sampling frequency and is
// attenuated far more. 0.4 km/h leaves room for the ticks where the speed estimate takes over.
constexpr double kSteadySdKmh = 0.4;

void expect_calm_and_legal(const DriveResult& r, const std::string& what) {
  EXPECT_LE(r.max_step, kMaxStepKmh) << what << ": shown value jitters";
  EXPECT_EQ(r.band_violations, 0) << what << ": outside the R39 band around the speed estimate";
  EXPECT_LE(r.worst_low, kEstimateErrorKmh) << what << ": reads below the true speed";
  EXPECT_LE(r.worst_high, kEstimateErrorKmh) << what << ": reads above 110 % + 4 km/h";
}

}  // namespace

TEST(Speedometer, RampsWithNoiseAreCalmAndInsideTheBand) {
  auto up = [](double t) { return std::min(150.0, 10.0 * t); };           // 0 -> 150 km/h at 10 km/h/s
  auto down = [](double t) { return std::max(0.0, 150.0 - 10.0 * t); };  // and back
  expect_calm_and_legal(drive(20, up, uniform_noise(1)), "ramp up, uniform noise");
  expect_calm_and_legal(drive(20, up, alternating_noise), "ramp up, alternating noise");
  expect_calm_and_legal(drive(20, down, uniform_noise(2)), "ramp down, uniform noise");
  expect_calm_and_legal(drive(20, down, alternating_noise), "ramp down, alternating noise");
}

TEST(Speedometer, SteadySpeedsWithNoiseAreCalmAndInsideTheBand) {
  for (double v : {30.0, 100.0, 200.0}) {
    auto steady = [v](double) { return v; };
    for (bool alternating : {false, true}) {
      const std::string what = "steady " + std::to_string(v) + (alternating ? ", alternating noise" : ", uniform noise");
      const DriveResult r = alternating ? drive(30, steady, alternating_noise) : drive(30, steady, uniform_noise(3));
      expect_calm_and_legal(r, what);
      EXPECT_LE(r.sd, kSteadySdKmh) << what << ": the shown value wanders";
    }
  }
}

TEST(Speedometer, EstimateFollowsARampWithoutLagAndSurvivesBadSteps) {
  SpeedEstimate e;
  e.reset(0);
  for (int k = 1; k <= 1000; ++k) e.step(0.1 * k, kDt);  // 10 km/h/s for 10 s, no noise
  EXPECT_NEAR(e.value(), 100.0, 0.01);                   // a steady ramp: no lag left
  const double before = e.value();
  EXPECT_EQ(e.step(std::nan(""), kDt), before);          // a NaN sample changes nothing
  EXPECT_EQ(e.step(50, 0.0), before);                    // nor does a zero or negative step
  EXPECT_EQ(e.step(50, -1.0), before);
  EXPECT_NEAR(e.step(50, 600.0), 50.0, 1e-9);            // a 10-minute stall: the sample as it is
  e.reset(-5);
  EXPECT_EQ(e.value(), 0.0);                             // never negative
  EXPECT_THROW(SpeedEstimate(0.0, 1.0), std::invalid_argument);
}
