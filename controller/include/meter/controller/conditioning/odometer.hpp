// Odometer and trip distance, integrated from the speed or a wheel-pulse counter.
// Pure and time-stepped: time comes in explicitly (nanoseconds on the input's clock), so tests
// and log replay are deterministic.
#pragma once

#include <cstdint>
#include <optional>

namespace meter::controller {

// Odometer and trip in integer micrometres: integer accumulation cannot drift or lose small steps
// at large totals the way a floating-point kilometre counter does. The sub-micrometre remainder of
// each step is carried, so integrating a constant speed gives the exact distance.
class Odometer {
 public:
  void add_speed(double speed_kmh, std::int64_t dt_ns);  // negative/NaN speed or dt: ignored
  // Wrapping distance counter (e.g. a 16-bit wheel-pulse counter): the first call only latches.
  void add_counter(std::uint64_t counter, unsigned bits, double um_per_count);
  std::int64_t total_um() const { return odo_um_; }
  std::int64_t trip_um() const { return trip_um_; }
  void set(std::int64_t odo_um, std::int64_t trip_um) { odo_um_ = odo_um; trip_um_ = trip_um; }
  void reset_trip() { trip_um_ = 0; }
  double total_km() const { return static_cast<double>(odo_um_) / 1e9; }
  double trip_km() const { return static_cast<double>(trip_um_) / 1e9; }

 private:
  std::int64_t odo_um_ = 0, trip_um_ = 0;
  std::int64_t rem_ = 0;  // speed integration remainder, in 1/3600 um
  double carry_ = 0;      // counter integration remainder, in um (< 1)
  std::optional<std::uint64_t> last_counter_;
};

// Shown distance: whole 0.1 km, never rounded up (an odometer must not read ahead of the truth).
double odometer_display_km(double km);

}  // namespace meter::controller
