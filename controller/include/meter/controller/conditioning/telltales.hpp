// Telltale (warning lamp) timing: blink patterns, bulb check, seat-belt reminder, thresholds.
// Pure and time-stepped: time comes in explicitly (nanoseconds on the input's clock), so tests
// and log replay are deterministic.
#pragma once

#include <cstdint>

namespace meter::controller {

// Telltale timing.
struct BlinkPattern {
  double period_s = 0.667;  // UN R48: 90 +/- 30 flashes per minute
  double duty = 0.5;
  // On/off at time t for a request that became active at t_on.
  bool lit(std::int64_t t_ns, std::int64_t t_on_ns) const;
};

// Bulb check: every telltale lit for a configured 2..4 s from the start (ignition on).
class BulbCheck {
 public:
  explicit BulbCheck(double duration_s = 3.0);  // throws std::invalid_argument outside 2..4 s
  void start(std::int64_t t_ns) { start_ = t_ns; started_ = true; }
  bool active(std::int64_t t_ns) const { return started_ && t_ns >= start_ && t_ns - start_ < dur_ns_; }
  double duration_s() const { return static_cast<double>(dur_ns_) / 1e9; }

 private:
  std::int64_t dur_ns_;
  std::int64_t start_ = 0;
  bool started_ = false;
};

// Seat-belt reminder (UN R16 style): with the driver's belt unbuckled, the lamp is lit steadily
// for first_level_s (4..8 s) after ignition on; afterwards it stays lit while unbuckled above
// speed_on_kmh and, above second_level_kmh, flashes (the second-level warning).
struct SeatBeltConfig {
  double first_level_s = 6.0;
  double speed_on_kmh = 10.0;
  double second_level_kmh = 25.0;
  BlinkPattern second_level_blink{1.0, 0.5};
};
class SeatBeltReminder {
 public:
  explicit SeatBeltReminder(SeatBeltConfig c = {});  // throws std::invalid_argument if first_level_s outside 4..8
  void ignition_on(std::int64_t t_ns) { ign_on_ = t_ns; ign_ = true; }
  void ignition_off() { ign_ = false; }
  bool lit(std::int64_t t_ns, bool unbuckled, double speed_kmh);

 private:
  SeatBeltConfig c_;
  std::int64_t ign_on_ = 0;
  bool ign_ = false;
  bool second_ = false;
  std::int64_t second_since_ = 0;
};

// Two-threshold comparator (fuel low, coolant over-temperature): on beyond 'on', off past 'off'.
struct Hysteresis {
  double on, off;
  bool below;  // true: lit when value < on, cleared when value > off
  bool state = false;
  bool update(double v);
};

}  // namespace meter::controller
