// Signal conditioning: the pure, time-stepped pieces of the cluster model. Every class takes the
// time explicitly (nanoseconds on the input's clock), so tests and log replay are deterministic.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

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

// UN ECE R39 speedometer rule: the shown speed never reads low and never reads more than
// 10 % + 4 km/h high: 0 <= shown - true <= 0.1 * true + 4.
struct SpeedometerRule {
  double ratio = 1.02;   // designed-in over-read, within the legal band
  double offset_kmh = 1.0;
  // 'displayed' is the damped needle value; the result is forced into the legal band around 'truth'.
  double apply(double displayed, double truth) const;
  static bool legal(double shown, double truth) { return shown >= truth && shown - truth <= 0.1 * truth + 4.0 + 1e-9; }
};

// Fuel gauge: sloshing is filtered heavily while driving and lightly while stopped; a level rise
// of at least refuel_delta while stopped, held for refuel_confirm, is a refuel and the gauge goes
// there at once; an invalid or implausible sender value held for fault_time drops the gauge to its
// fault look.
struct FuelFilterConfig {
  double tau_moving_s = 60.0;
  double tau_stopped_s = 4.0;
  double stopped_below_kmh = 2.0;
  double refuel_delta = 5.0;       // percent
  double refuel_confirm_s = 2.0;
  double fault_time_s = 3.0;
  double plausible_min = -5.0, plausible_max = 105.0;  // sender raw percent outside = fault
};
class FuelFilter {
 public:
  explicit FuelFilter(FuelFilterConfig c = {}) : c_(c) {}
  // sample_valid: the sender delivered a usable value this step.
  void step(double level, bool sample_valid, double speed_kmh, double dt_s);
  bool has_value() const { return init_; }
  bool fault() const { return fault_; }
  double value() const { return y_; }
  int refuels() const { return refuels_; }

 private:
  FuelFilterConfig c_;
  double y_ = 0;
  bool init_ = false, fault_ = false;
  double bad_for_ = 0, rise_for_ = 0;
  int refuels_ = 0;
};

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

// Atomic persistence of the odometer: write a temp file, fsync it, rename over the old one, fsync
// the directory. A kill at any instant leaves either the old or the new complete file. The record
// carries a CRC so a damaged file is detected instead of trusted.
struct OdometerRecord {
  std::int64_t odo_um = 0, trip_um = 0;
  std::uint64_t sequence = 0;  // increments per save
};
class OdometerStore {
 public:
  explicit OdometerStore(std::string dir);  // creates the directory if needed
  // nullopt when nothing was stored yet; throws std::runtime_error naming the file if it is corrupt.
  std::optional<OdometerRecord> load() const;
  void save(const OdometerRecord& r);  // throws std::runtime_error on I/O failure
  const std::string& path() const { return path_; }
  static std::string format(const OdometerRecord& r);
  static std::optional<OdometerRecord> parse(const std::string& text, std::string* why);

 private:
  std::string dir_, path_;
};

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
