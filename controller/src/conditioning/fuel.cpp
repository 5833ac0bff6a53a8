#include "meter/controller/conditioning/fuel.hpp"

#include <algorithm>
#include <cmath>

namespace meter::controller {

void FuelFilter::step(double level, bool valid, double speed, double dt) {
  if (!(dt >= 0) || !std::isfinite(dt)) dt = 0;
  bool plausible = valid && std::isfinite(level) && level >= c_.plausible_min && level <= c_.plausible_max;
  if (!plausible) {
    bad_for_ += dt;
    if (bad_for_ >= c_.fault_time_s) fault_ = true;
    return;
  }
  bad_for_ = 0;
  level = std::clamp(level, 0.0, 100.0);
  if (!init_ || fault_) {  // first value, or recovering from a sender fault: show the truth at once
    y_ = level;
    init_ = true;
    fault_ = false;
    rise_for_ = 0;
    return;
  }
  bool stopped = std::isfinite(speed) && speed < c_.stopped_below_kmh;
  if (stopped && level - y_ >= c_.refuel_delta) {
    rise_for_ += dt;
    if (rise_for_ >= c_.refuel_confirm_s) {
      y_ = level;
      rise_for_ = 0;
      ++refuels_;
      return;
    }
  } else {
    rise_for_ = 0;
  }
  const double tau = stopped ? c_.tau_stopped_s : c_.tau_moving_s;
  y_ += (level - y_) * (1.0 - std::exp(-dt / tau));
}

}  // namespace meter::controller
