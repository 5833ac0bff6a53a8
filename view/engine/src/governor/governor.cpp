// The frame-rate governor (governor.hpp).
#include "meter/engine/governor/governor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "governor/cost_limits.hpp"

namespace meter::engine::governor {
namespace {

GovernorOptions checked(const GovernorOptions& o) {
  if (!std::isfinite(o.target_ms) || !(o.target_ms > 0))
    throw std::invalid_argument("governor: target_ms must be a finite number > 0");
  if (!(o.headroom >= 0 && o.headroom <= 0.5)) throw std::invalid_argument("governor: headroom must be in [0, 0.5]");
  if (o.min_frames_between_changes < 0)
    throw std::invalid_argument("governor: min_frames_between_changes must be >= 0");
  if (o.fast_attack_frames < 0) throw std::invalid_argument("governor: fast_attack_frames must be >= 0");
  return o;
}

}  // namespace

std::string reduced_summary(const GovernorState& state) {
  std::string s;
  for (const ReducedUnit& u : state.reduced)
    s += (s.empty() ? "" : " ") + u.name + "=" + bridge::to_string(u.shading) + "/lod" + std::to_string(u.level.lod);
  return s;
}

Governor::Governor(CostModel model, GovernorOptions options)
    : model_(std::move(model)),
      options_(checked(options)),
      online_(options.window),
      current_(full_quality(model_)),
      frames_since_change_(options.min_frames_between_changes) {
  limits::check_model(model_, "governor cost model");
}

QualityChoice Governor::choose(const FrameLoad& load) {
  if (!load.drawn) {
    predicted_ms_ = 0.0;
    return current_;
  }
  ++frames_chosen_;
  frames_since_change_ = std::min(frames_since_change_ + 1, 1 << 30);  // no overflow in a year-long run
  if (load.full_frame && load.unit_pixels.size() == model_.units.size()) last_full_load_ = load;
  const ModelScale scale = this->scale();
  if (frames_since_change_ < options_.min_frames_between_changes) {
    predicted_ms_ = predict_ms(model_, load, current_, scale);
    if (predicted_ms_ <= options_.target_ms) return current_;  // a step up waits; a step down does not
  }
  const GreedyBudget budget{options_.target_ms, (1.0 - options_.headroom) * options_.target_ms};
  GreedyResult r = greedy_choice(model_, load, current_, budget, scale, last_full_load_ ? &*last_full_load_ : nullptr);
  predicted_ms_ = r.predicted_ms;
  if (r.choice != current_) {
    current_ = std::move(r.choice);
    ++changes_;
    frames_since_change_ = 0;
  }
  return current_;
}

void Governor::observe(const FrameLoad& load, const QualityChoice& choice, double measured_ms) {
  const PredictionParts parts = predict_parts(model_, load, choice);  // validates the choice
  if (!load.drawn || !std::isfinite(measured_ms) || !(measured_ms > 0)) return;
  const double predicted = parts.total(online_.scale());
  if (options_.fast_attack_frames > 0 && predicted > 0 && std::isfinite(predicted)) {
    recent_ratios_.push_back(measured_ms / predicted);
    while (int(recent_ratios_.size()) > options_.fast_attack_frames) recent_ratios_.pop_front();
  }
  if (online_.add(parts, measured_ms)) {
    measured_ms_ = measured_ms;
    ++frames_observed_;
  }
}

double Governor::fast_attack() const {
  if (options_.fast_attack_frames == 0 || int(recent_ratios_.size()) < options_.fast_attack_frames) return 1.0;
  const double least = *std::min_element(recent_ratios_.begin(), recent_ratios_.end());
  return least > 1.0 + options_.headroom ? std::min(least, OnlineEstimate::kMaxScale) : 1.0;
}

ModelScale Governor::scale() const {
  const ModelScale s = online_.scale();
  const double f = fast_attack();
  return {std::min(s.pixel * f, OnlineEstimate::kMaxScale), std::min(s.fixed * f, OnlineEstimate::kMaxScale)};
}

GovernorState Governor::state() const {
  GovernorState s{.frames_chosen = frames_chosen_,
                  .frames_observed = frames_observed_,
                  .changes = changes_,
                  .frames_since_change = frames_since_change_,
                  .predicted_ms = predicted_ms_,
                  .measured_ms = measured_ms_,
                  .scale = scale(),
                  .fast_attack = fast_attack(),
                  .global_rung = std::max(0, global_rung(model_, current_.global)),
                  .global = current_.global,
                  .reduced = {}};
  for (std::size_t u = 0; u < current_.units.size(); ++u) {
    const UnitLevel& l = current_.units[u];
    if (l == UnitLevel{}) continue;
    s.reduced.push_back({int(u), model_.units[u].name, l, model_.units[u].at(l).shading});
  }
  return s;
}

}  // namespace meter::engine::governor
