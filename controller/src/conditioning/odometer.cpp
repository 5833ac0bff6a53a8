#include "meter/controller/conditioning/odometer.hpp"

#include <cmath>

namespace meter::controller {

void Odometer::add_speed(double speed_kmh, std::int64_t dt_ns) {
  if (!(speed_kmh > 0) || !std::isfinite(speed_kmh) || dt_ns <= 0) return;
  // km/h * ns / 3600 = micrometres. The product v * dt is an integer for any speed with the
  // resolution a DBC gives it (0.01 km/h * 1e6 ns...), so it is counted in integer units of 1/3600
  // um and carried exactly: no rounding drift however long the car drives.
  const double product = std::nearbyint(speed_kmh * static_cast<double>(dt_ns));
  if (!(product < 9.0e18)) return;  // a glitch of absurd size: refuse rather than overflow
  const std::int64_t units = static_cast<std::int64_t>(product) + rem_;
  const std::int64_t add = units / 3600;
  rem_ = units % 3600;
  odo_um_ += add;
  trip_um_ += add;
}

void Odometer::add_counter(std::uint64_t counter, unsigned bits, double um_per_count) {
  const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
  counter &= mask;
  if (last_counter_) {
    std::uint64_t delta = (counter - *last_counter_) & mask;  // wraps correctly
    double um = static_cast<double>(delta) * um_per_count + carry_;
    // A NaN or negative scale, or a jump too large for int64, would reach an undefined double ->
    // int64 conversion (or count backwards): latch the counter and add nothing.
    if (!(um >= 0 && um < 9.0e18)) {
      last_counter_ = counter;
      return;
    }
    double whole = std::floor(um);
    carry_ = um - whole;
    odo_um_ += static_cast<std::int64_t>(whole);
    trip_um_ += static_cast<std::int64_t>(whole);
  }
  last_counter_ = counter;
}

double odometer_display_km(double km) { return std::floor(km * 10.0) / 10.0; }

}  // namespace meter::controller
