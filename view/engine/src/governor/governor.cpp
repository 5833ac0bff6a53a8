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
  if (!(o.miss_share >= 0 && o.miss_share < 0.5)) throw std::invalid_argument("governor: miss_share must be in [0, 0.5)");
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
      frames_since_change_(options.min_frames_between_changes),
      step_up_wait_(options.min_frames_between_changes) {
  limits::check_model(model_, "governor cost model");
  corrected_ = model_;
  rung_error_.assign(model_.globals.size(), 1.0);
}

QualityChoice Governor::choose(const FrameLoad& load) {
  if (!load.drawn) {
    predicted_ms_ = 0.0;
    return current_;
  }
  ++frames_chosen_;
  frames_since_change_ = std::min(frames_since_change_ + 1, 1 << 30);  // no overflow in a year-long run
  frames_since_step_up_ = std::min(frames_since_step_up_ + 1, 1 << 30);
  if (late_backoff_ > 0 && frames_since_step_up_ >= options_.window) {  // the last step up stayed
    late_backoff_ = 0;
    if (!last_change_up_) step_up_wait_ = options_.min_frames_between_changes;
  }
  if (load.full_frame && load.unit_pixels.size() == model_.units.size()) last_full_load_ = load;
  frames_since_readback_ = load.read_back ? 0 : std::min(frames_since_readback_ + 1, 1 << 30);
  const double reserve = readback_reserve(load);
  readback_reserved_ = reserve > 0;
  const ModelScale scale = this->scale();
  if (undo_pending_) {  // the step up just taken missed the target: back to where it came from
    undo_pending_ = false;
    last_change_global_ = !(before_step_up_.global == current_.global);
    current_ = before_step_up_;
    last_change_up_ = false;
    ++changes_;
    ++step_ups_undone_;
    frames_since_change_ = 0;
    step_up_wait_ = std::min(std::max(1, 2 * step_up_wait_), kMaxStepUpWait);
  } else if (last_change_up_ && frames_since_change_ >= std::max(step_up_wait_, judged_frame() + 1)) {
    step_up_wait_ = std::max(options_.min_frames_between_changes, late_backoff_);  // the step up held its judged frames
    last_change_up_ = false;
    const int rung = last_change_global_ ? global_rung(model_, current_.global) : -1;
    if (rung >= 0 && rung_error_[std::size_t(rung)] > 1.0) set_rung_error(rung, 0.5 * (rung_error_[std::size_t(rung)] + 1.0));
  }
  const double now_ms = predict_ms(corrected_, load, current_, scale) + reserve;
  // What the drawing may take: the target less the readback, divided by the spread.
  const double limit = (options_.target_ms - reserve) / spread();
  if (frames_since_change_ < step_up_wait_ && now_ms - reserve <= limit) {
    predicted_ms_ = now_ms;
    return current_;  // a step up waits; a step down does not
  }
  const GreedyBudget budget{limit, (1.0 - options_.headroom) * limit};
  GreedyResult r = greedy_choice(corrected_, load, current_, budget, scale, last_full_load_ ? &*last_full_load_ : nullptr);
  predicted_ms_ = r.predicted_ms + reserve;
  if (r.choice != current_) {
    last_change_up_ = predicted_ms_ > now_ms;
    last_change_global_ = !(r.choice.global == current_.global);
    if (last_change_up_) {
      before_step_up_ = current_;
      frames_since_step_up_ = 0;
    } else if (frames_since_step_up_ < options_.window) {
      // A step down within a window of the last step up: that step up did not last either (the
      // model drifted back), so the next one waits twice as long; a flapping choice settles.
      late_backoff_ = std::min(std::max(2 * late_backoff_, 2 * options_.min_frames_between_changes), kMaxStepUpWait);
      step_up_wait_ = std::max(step_up_wait_, late_backoff_);
    }
    current_ = std::move(r.choice);
    ++changes_;
    frames_since_change_ = 0;
  }
  return current_;
}

void Governor::observe(const FrameLoad& load, const QualityChoice& choice, double measured_ms) {
  // Against the model the choice was made on, rung errors included: the window and the fast
  // attack learn what is left, and a rung's error is not counted twice.
  const PredictionParts parts = predict_parts(corrected_, load, choice);  // validates the choice
  if (!load.drawn || !std::isfinite(measured_ms) || !(measured_ms > 0)) return;
  // A rung change's own frame (new targets, everything redrawn) says nothing about the frames
  // after it: neither the window nor the fast attack sees it.
  if (last_change_global_ && frames_since_change_ == 0 && choice == current_) return;
  const double predicted = parts.total(online_.scale());
  // A read-back frame: what it measured beyond the drawing's prediction is the readback's sample;
  // the rest of this function sees the drawing alone.
  double drawing_ms = measured_ms;
  if (load.read_back) {
    const double sample = std::max(0.0, measured_ms - parts.total(scale()));
    readback_ms_ = readback_known_ ? 0.5 * (readback_ms_ + sample) : sample;
    readback_known_ = true;
    drawing_ms = std::max(measured_ms - readback_ms_, 1e-3 * measured_ms);
  }
  if (options_.fast_attack_frames > 0 && predicted > 0 && std::isfinite(predicted)) {
    // Only a frame over the budget counts as slow: a frame well within it (a partial redraw of a
    // few pixels, whose prediction is mostly the fixed overhead) threatens nothing, however far
    // off the model is for it.
    const bool over_budget = drawing_ms > (1.0 - options_.headroom) * options_.target_ms - readback_reserve(load);
    recent_ratios_.push_back(over_budget ? drawing_ms / predicted : 0.0);
    while (int(recent_ratios_.size()) > options_.fast_attack_frames) recent_ratios_.pop_front();
  }
  // The first frame drawn with a step up measured over the target: the model was wrong about it.
  if (last_change_up_ && frames_since_change_ == judged_frame() && choice == current_ && measured_ms > options_.target_ms) {
    undo_pending_ = true;
    // The rung's own error, which the common scale does not have: its predictions carry it from now on.
    const int rung = last_change_global_ ? global_rung(model_, choice.global) : -1;
    if (rung >= 0 && predicted > 0 && std::isfinite(predicted) && drawing_ms > predicted)
      set_rung_error(rung, rung_error_[std::size_t(rung)] * drawing_ms / predicted);
  }
  if (online_.add(parts, drawing_ms)) {
    measured_ms_ = measured_ms;
    ++frames_observed_;
  }
}

void Governor::set_rung_error(int rung, double error) {
  const std::size_t r = std::size_t(rung);
  rung_error_[r] = std::clamp(error, 1.0, OnlineEstimate::kMaxScale);
  corrected_.globals[r].pixel_factor = model_.globals[r].pixel_factor * rung_error_[r];
  corrected_.globals[r].fixed_ms = model_.globals[r].fixed_ms * rung_error_[r];
}

double Governor::readback_reserve(const FrameLoad& load) const {
  if (!readback_known_ || !(load.read_back || frames_since_readback_ < options_.window)) return 0.0;
  return std::min(readback_ms_, 0.5 * options_.target_ms);
}

// A rung change's own frame is left out: it makes the new targets and redraws everything, which
// happens once, not every frame at that rung; the frame after it is judged.
int Governor::judged_frame() const { return last_change_global_ ? 1 : 0; }

double Governor::fast_attack() const {
  if (options_.fast_attack_frames == 0 || int(recent_ratios_.size()) < options_.fast_attack_frames) return 1.0;
  const double least = *std::min_element(recent_ratios_.begin(), recent_ratios_.end());
  return least > 1.0 + options_.headroom ? std::min(least, OnlineEstimate::kMaxScale) : 1.0;
}

double Governor::spread() const {
  if (options_.miss_share <= 0) return 1.0;
  return std::min(online_.upper_ratio(options_.miss_share, 0.5 * options_.target_ms), kMaxSpread);
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
                  .spread = spread(),
                  .step_ups_undone = step_ups_undone_,
                  .step_up_wait = step_up_wait_,
                  .readback_ms = readback_ms_,
                  .readback_reserved = readback_reserved_,
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
