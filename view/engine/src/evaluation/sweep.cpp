// The start-up sweep: at ignition on the needles go to full scale and back before they show
// their values. The bindings keep following their signals meanwhile, so nothing that arrives
// during the sweep is lost: it is what the needles show when the sweep ends.
#include <algorithm>

#include "meter/engine/evaluation/scene_features.hpp"

namespace meter::engine {

std::optional<double> sweep_position(const SweepConfig& s, double t_s) {
  const double rise = s.rise_ms / 1000.0, hold = s.hold_ms / 1000.0, fall = s.fall_ms / 1000.0;
  auto ease = [](double x) { return x * x * (3.0 - 2.0 * x); };
  if (t_s < 0) return 0.0;
  if (t_s < rise) return ease(t_s / rise);
  if (t_s < rise + hold) return 1.0;
  if (t_s < rise + hold + fall) return 1.0 - ease((t_s - rise - hold) / fall);
  return std::nullopt;
}

void SweepTimeline::update(std::optional<double> ignition, double dt) {
  just_ended_ = false;
  const bool on = ignition && *ignition >= config_.on_at_least;
  if (running_) {
    t_s_ += std::max(dt, 0.0);
    if (!sweep_position(config_, t_s_)) running_ = false, just_ended_ = true;
  }
  // Only a live clock sweeps: an offline render shows the state itself.
  if (on && !was_on_ && dt >= 0) running_ = true, t_s_ = 0.0, just_ended_ = false;
  // Ignition off during the sweep ends it: the needles show their (failsafe) values.
  if (ignition && !on && running_) running_ = false, just_ended_ = true;
  if (ignition) was_on_ = on;
}

}  // namespace meter::engine
