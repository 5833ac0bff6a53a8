#include "meter/controller/conditioning/telltales.hpp"

#include <cmath>
#include <stdexcept>

namespace meter::controller {

bool BlinkPattern::lit(std::int64_t t, std::int64_t t_on) const {
  if (t < t_on) return false;
  if (!(period_s > 0) || period_s > 1e6) return true;  // no sensible period: steady
  const auto period = static_cast<std::int64_t>(period_s * 1e9);
  if (period <= 0) return true;
  const std::int64_t phase = (t - t_on) % period;
  return static_cast<double>(phase) < duty * static_cast<double>(period);
}

BulbCheck::BulbCheck(double d) {
  if (!(d >= 2.0 && d <= 4.0)) throw std::invalid_argument("bulb check duration must be 2..4 s, got " + std::to_string(d));
  dur_ns_ = static_cast<std::int64_t>(d * 1e9);
}

SeatBeltReminder::SeatBeltReminder(SeatBeltConfig c) : c_(c) {
  if (!(c.first_level_s >= 4.0 && c.first_level_s <= 8.0))
    throw std::invalid_argument("seat-belt first-level warning must last 4..8 s, got " + std::to_string(c.first_level_s));
}

bool SeatBeltReminder::lit(std::int64_t t, bool unbuckled, double speed) {
  if (!ign_ || !unbuckled) {
    second_ = false;
    return false;
  }
  if (!std::isfinite(speed)) speed = 0;
  if (speed > c_.second_level_kmh) {
    if (!second_) {
      second_ = true;
      second_since_ = t;
    }
    return c_.second_level_blink.lit(t, second_since_);
  }
  second_ = false;
  if (t - ign_on_ < static_cast<std::int64_t>(c_.first_level_s * 1e9)) return true;
  return speed > c_.speed_on_kmh;
}

bool Hysteresis::update(double v) {
  if (!std::isfinite(v)) return state;
  if (below) {
    if (v < on) state = true;
    else if (v > off) state = false;
  } else {
    if (v > on) state = true;
    else if (v < off) state = false;
  }
  return state;
}

}  // namespace meter::controller
