// Gauge needles: critically damped pointer motion and the UN ECE R39 speedometer band.
// Pure and time-stepped: time comes in explicitly (nanoseconds on the input's clock), so tests
// and log replay are deterministic.
#pragma once

namespace meter::controller {

// Critically damped second-order needle filter, x'' + 2w x' + w^2 x = w^2 u, integrated in closed
// form for a target held over the step: exact for any dt (0, 1 ms, a 10-minute stall), never NaN.
// A needle must not swing past the value it is heading to, so if a step would cross the target the
// needle stops on it (only possible when it was already moving when the target changed).
class NeedleFilter {
 public:
  explicit NeedleFilter(double time_constant_s = 0.2);
  void reset(double value);  // jump (first value, or after a fault)
  // Advances by dt_s toward target; returns the new position. Non-finite target or dt: no change.
  double step(double target, double dt_s);
  double value() const { return x_; }
  double velocity() const { return v_; }
  bool initialized() const { return init_; }

 private:
  double w_;
  double x_ = 0, v_ = 0;
  bool init_ = false;
};

// The true vehicle speed estimated from noisy speed samples, for the R39 band: double exponential
// smoothing (a level and a trend, each a first-order filter with its own time constant, weights
// 1 - exp(-dt / tau) so any dt is exact), so sample noise is attenuated while a steady acceleration
// is followed without lag: the band does not fall behind the car on a ramp.
class SpeedEstimate {
 public:
  explicit SpeedEstimate(double level_tau_s = 0.2, double trend_tau_s = 0.5);
  void reset(double speed);  // first sample, or after an invalid spell: the sample as it is
  // Advances by dt_s with a new sample; returns the estimate (>= 0). Non-finite sample or dt: no change.
  double step(double sample, double dt_s);
  double value() const { return level_; }
  bool initialized() const { return init_; }

 private:
  double level_tau_, trend_tau_;
  double level_ = 0, trend_ = 0;  // km/h and km/h per second
  bool init_ = false;
};

// UN ECE R39 speedometer rule: the shown speed never reads low and never reads more than
// 10 % + 4 km/h high: 0 <= shown - true <= 0.1 * true + 4.
struct SpeedometerRule {
  double ratio = 1.02;   // designed-in over-read, within the legal band
  double offset_kmh = 1.0;
  // 'displayed' is the damped needle value; the result is forced into the legal band around 'truth'
  // (the estimated true speed, SpeedEstimate: a raw sample's noise must not reach the needle).
  double apply(double displayed, double truth) const;
  static bool legal(double shown, double truth) { return shown >= truth && shown - truth <= 0.1 * truth + 4.0 + 1e-9; }
};

}  // namespace meter::controller
