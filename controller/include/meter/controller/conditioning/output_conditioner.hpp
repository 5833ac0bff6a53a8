// The conditioning chain of one catalog signal: what the gauge or lamp shows for its mapped value.
// Gauges: the fuel filter or the damped needle, then the UN R39 speedometer band (held around an
// estimate of the true speed, so the damped needle is never replaced by a noisy sample). Telltales: the
// request (optionally inverted), the seat-belt reminder, the blink pattern. Threshold rules (low
// fuel, coolant over-temperature) light a lamp from another signal's shown value with hysteresis.
#pragma once

#include <cstdint>
#include <optional>

#include "meter/controller/conditioning/fuel.hpp"
#include "meter/controller/conditioning/needle.hpp"
#include "meter/controller/conditioning/telltales.hpp"
#include "meter/controller/mapping/apply.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::controller {

class OutputConditioner {
 public:
  OutputConditioner(const OutputMapping& m, protocol::SignalKind kind);

  bool telltale() const { return telltale_; }
  bool threshold_rule() const { return hysteresis_.has_value(); }

  // mapped: the mapping stage's value at t_ns (the true value); speed_kmh: the true vehicle speed
  // when known (fuel slosh filtering and the seat-belt reminder depend on it).
  OutputValue condition(const OutputValue& mapped, std::int64_t t_ns, double dt_s, std::optional<double> speed_kmh);
  // Threshold rule on the watched signal's shown value (nullopt: that signal is not mapped).
  OutputValue threshold(const std::optional<OutputValue>& watched);
  // The speedometer's estimate of the true speed that its R39 band is held around (nullopt: not a
  // speedometer, or no valid speed yet).
  std::optional<double> speed_estimate() const;

  // Ignition on restarts the seat-belt reminder's first level; off stops it.
  void ignition_on(std::int64_t t_ns) {
    if (belt_) belt_->ignition_on(t_ns);
  }
  void ignition_off() {
    if (belt_) belt_->ignition_off();
  }

 private:
  bool telltale_;
  // Gauges.
  std::optional<SpeedometerRule> speedometer_;
  SpeedEstimate truth_;  // speedometers: the true speed the R39 band is held around
  std::optional<NeedleFilter> needle_;
  std::optional<FuelFilter> fuel_;
  bool was_valid_ = false;  // after an invalid spell the needle jumps to the value instead of sweeping
  // Telltales.
  bool invert_;
  std::optional<BlinkPattern> blink_;
  std::optional<SeatBeltReminder> belt_;
  std::optional<Hysteresis> hysteresis_;  // threshold rules
  bool request_ = false;
  std::int64_t request_since_ = 0;  // the blink phase runs from here
};

}  // namespace meter::controller
