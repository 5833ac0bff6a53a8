#include "meter/controller/conditioning/needle.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace meter::controller {

NeedleFilter::NeedleFilter(double tau) {
  if (!(tau > 0) || !std::isfinite(tau)) throw std::invalid_argument("needle time constant must be > 0 s");
  w_ = 1.0 / tau;
}

void NeedleFilter::reset(double value) {
  if (!std::isfinite(value)) return;
  x_ = value;
  v_ = 0;
  init_ = true;
}

double NeedleFilter::step(double target, double dt) {
  if (!std::isfinite(target)) return x_;
  if (!init_) {
    reset(target);
    return x_;
  }
  if (!(dt > 0) || !std::isfinite(dt)) return x_;  // dt = 0 (or garbage): nothing moves
  // e(t) = (e0 + (v0 + w e0) t) exp(-w t),  v(t) = (v0 - w (v0 + w e0) t) exp(-w t).
  // For huge w*t exp() underflows to 0 and t*0 = 0: the needle is simply at the target.
  const double e0 = x_ - target;
  const double k = v_ + w_ * e0;
  const double wt = w_ * dt;
  const double decay = wt > 700 ? 0.0 : std::exp(-wt);
  double e = (e0 + k * dt) * decay;
  double v = (v_ - w_ * k * dt) * decay;
  if (!std::isfinite(e) || !std::isfinite(v)) {
    e = 0;
    v = 0;
  }
  if (e0 != 0 && (e > 0) != (e0 > 0) && e != 0) {  // would cross the target: stop on it
    e = 0;
    v = 0;
  }
  x_ = target + e;
  v_ = v;
  return x_;
}

SpeedEstimate::SpeedEstimate(double level_tau, double trend_tau) : level_tau_(level_tau), trend_tau_(trend_tau) {
  if (!(level_tau > 0) || !std::isfinite(level_tau) || !(trend_tau > 0) || !std::isfinite(trend_tau))
    throw std::invalid_argument("speed estimate time constants must be > 0 s");
}

void SpeedEstimate::reset(double speed) {
  if (!std::isfinite(speed)) return;
  level_ = std::max(0.0, speed);
  trend_ = 0;
  init_ = true;
}

double SpeedEstimate::step(double sample, double dt) {
  if (!std::isfinite(sample)) return level_;
  if (!init_) {
    reset(sample);
    return level_;
  }
  if (!(dt > 0) || !std::isfinite(dt)) return level_;
  // Holt's method with time-continuous weights: predict along the trend, blend in the sample, then
  // blend the level's change into the trend. After a long stall (dt >> tau) both weights are 1: the
  // estimate is the sample and the trend the average slope over the stall.
  const double a = 1.0 - std::exp(-dt / level_tau_), b = 1.0 - std::exp(-dt / trend_tau_);
  const double predicted = level_ + trend_ * dt;
  const double level = predicted + a * (sample - predicted);
  trend_ += b * ((level - level_) / dt - trend_);
  level_ = std::max(0.0, level);
  if (!std::isfinite(level_) || !std::isfinite(trend_)) reset(sample);
  return level_;
}

double SpeedometerRule::apply(double displayed, double truth) const {
  if (!std::isfinite(truth) || truth < 0) truth = 0;
  if (!std::isfinite(displayed)) displayed = truth;
  double shown = displayed * ratio + offset_kmh;
  const double lo = truth, hi = truth * 1.1 + 4.0;
  if (shown < lo) shown = lo;
  if (shown > hi) shown = hi;
  return shown;
}

}  // namespace meter::controller
