// Fuel gauge conditioning: slosh filter, refuel detection and sender fault.
// Pure and time-stepped: time comes in explicitly (nanoseconds on the input's clock), so tests
// and log replay are deterministic.
#pragma once

namespace meter::controller {

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

}  // namespace meter::controller
