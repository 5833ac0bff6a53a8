#include "meter/controller/conditioning/output_conditioner.hpp"

namespace meter::controller {

using protocol::SignalStatus;

OutputConditioner::OutputConditioner(const OutputMapping& m, protocol::SignalKind kind)
    : telltale_(kind == protocol::SignalKind::Telltale), speedometer_(m.speedometer), invert_(m.invert), blink_(m.blink) {
  if (m.needle_tau_s > 0) needle_.emplace(m.needle_tau_s);
  if (m.fuel) fuel_.emplace(m.fuel_config);
  if (m.rule == Rule::SeatBelt) belt_.emplace(m.seat_belt);
  if (m.rule == Rule::Below || m.rule == Rule::Above) hysteresis_ = Hysteresis{m.rule_on, m.rule_off, m.rule == Rule::Below};
}

OutputValue OutputConditioner::threshold(const std::optional<OutputValue>& watched) {
  if (watched && watched->status == SignalStatus::Valid)
    return {hysteresis_->update(watched->value) ? 1.0 : 0.0, SignalStatus::Valid};
  return {0.0, watched ? watched->status : SignalStatus::NotAvailable};
}

std::optional<double> OutputConditioner::speed_estimate() const {
  if (!speedometer_ || !was_valid_ || !truth_.initialized()) return std::nullopt;
  return truth_.value();
}

OutputValue OutputConditioner::condition(const OutputValue& mapped, std::int64_t t, double dt,
                                         std::optional<double> speed_kmh) {
  const double value = mapped.value;
  const bool truth_valid = mapped.status == SignalStatus::Valid;
  SignalStatus status = mapped.status;
  double shown = value;
  if (fuel_) {
    fuel_->step(value, truth_valid, speed_kmh.value_or(0.0), dt);
    if (fuel_->fault()) {
      status = SignalStatus::Invalid;
      shown = 0;
    } else if (fuel_->has_value()) {
      status = SignalStatus::Valid;
      shown = fuel_->value();
    } else if (status == SignalStatus::Valid) {
      status = SignalStatus::NotAvailable;
    }
  } else if (needle_ && status == SignalStatus::Valid) {
    if (!was_valid_) needle_->reset(value);
    else needle_->step(value, dt);
    shown = needle_->value();
  }
  // Damping first, then the legal band on the damped value, against the estimated true speed: a band
  // around the raw sample would hand its noise to the needle whenever the needle lags.
  if (speedometer_ && status == SignalStatus::Valid) {
    if (!was_valid_) truth_.reset(value);
    else truth_.step(value, dt);
    shown = speedometer_->apply(shown, truth_.value());
  }
  if (telltale_) {
    const bool req = status == SignalStatus::Valid && ((value != 0) != invert_);
    if (req && !request_) request_since_ = t;
    request_ = req;
    bool lit = req;
    if (belt_) {
      lit = belt_->lit(t, req, speed_kmh.value_or(0.0));
      if (status != SignalStatus::Valid) status = SignalStatus::Valid, lit = false;
    }
    if (blink_ && req) lit = blink_->lit(t, request_since_);
    shown = lit ? 1.0 : 0.0;
  }
  was_valid_ = status == SignalStatus::Valid;
  return {status == SignalStatus::Valid || status == SignalStatus::TimedOut ? shown : 0.0, status};
}

}  // namespace meter::controller
