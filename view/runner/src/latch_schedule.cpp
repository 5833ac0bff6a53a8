#include "meter/runner/latch_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "meter/runner/view_error.hpp"

namespace meter::runner {

LatchPacing parse_latch_pacing(const std::string& text) {
  if (text == "late") return LatchPacing::Late;
  if (text == "callback") return LatchPacing::Callback;
  throw ViewError("--latch: expected callback or late, got \"" + text + "\"");
}

const char* latch_pacing_name(LatchPacing pacing) { return pacing == LatchPacing::Late ? "late" : "callback"; }

const char* latch_reason_name(LatchReason reason) {
  switch (reason) {
    case LatchReason::Late: return "late";
    case LatchReason::NoPeriod: return "no refresh period yet";
    case LatchReason::NoLatch: return "no latch seen yet";
    case LatchReason::Idle: return "compositor idle";
    case LatchReason::NoFeedback: return "no presentation feedback";
    case LatchReason::RenderTooLong: return "render too long for the period";
  }
  return "?";
}

LatchSchedule::LatchSchedule(LatchSettings settings) : s_(settings), margin_ns_(settings.max_margin_ns) {}

void LatchSchedule::latched(std::int64_t t_ns) {
  if (t_ns > last_latch_ns_) last_latch_ns_ = t_ns;
}

void LatchSchedule::committed(std::uint64_t frame, const LatchDecision& decision, std::int64_t start_ns,
                              std::int64_t committed_ns) {
  renders_.push_back(std::max<std::int64_t>(0, committed_ns - start_ns));
  if (renders_.size() > s_.render_window) renders_.pop_front();
  if (decision.target_ns != 0) awaiting_[frame] = {decision.target_ns, decision.margin_ns, committed_ns};
}

void LatchSchedule::presented(std::uint64_t frame, bool discarded, std::int64_t presented_ns, std::int64_t refresh_ns) {
  if (refresh_ns > 0) period_ns_ = refresh_ns;
  // Feedback comes in presentation order: frames before this one without any were never shown.
  awaiting_.erase(awaiting_.begin(), awaiting_.lower_bound(frame));
  const auto it = awaiting_.find(frame);
  if (it == awaiting_.end()) return;
  const Awaiting drawn = it->second;
  awaiting_.erase(it);
  if (discarded) return judge(drawn, true);
  offsets_.push_back(presented_ns - drawn.target_ns);
  if (offsets_.size() > s_.offset_window) offsets_.pop_front();
  // On time, a frame is presented as long after its latch as most of the recent ones (the median:
  // a frame that rendered faster than its estimate may make a latch before its target and come a
  // refresh earlier); a frame that missed its latch comes a refresh later than that.
  std::vector<std::int64_t> sorted(offsets_.begin(), offsets_.end());
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  judge(drawn, period_ns_ > 0 && offsets_.back() > sorted[sorted.size() / 2] + period_ns_ / 2);
}

void LatchSchedule::judge(const Awaiting& frame, bool missed) {
  if (missed) {
    ++missed_;
    run_ = 0;
    // Committed before the predicted latch and still late: the prediction was off by more than
    // the frame's margin; the start never settles back to it (the step it settled by over it).
    // Frames started with the same margin before the first miss was heard of move it once.
    if (frame.committed_ns < frame.target_ns)
      floor_ns_ = std::max(floor_ns_, frame.margin_ns + (settled_ ? s_.on_time_step_ns : s_.settle_step_ns));
    settled_ = true;
    margin_ns_ = std::min(std::max(margin_ns_, frame.margin_ns + s_.miss_step_ns), s_.max_margin_ns);
    return;
  }
  ++on_time_;
  if (++run_ < (settled_ ? s_.on_time_run : s_.settle_run)) return;
  run_ = 0;
  const std::int64_t lowest = std::min(std::max(s_.min_margin_ns, floor_ns_), s_.max_margin_ns);
  margin_ns_ = std::max(lowest, margin_ns_ - (settled_ ? s_.on_time_step_ns : s_.settle_step_ns));
}

std::int64_t LatchSchedule::render_estimate_ns() const {
  if (renders_.empty()) return 0;
  std::vector<std::int64_t> sorted(renders_.begin(), renders_.end());
  std::sort(sorted.begin(), sorted.end());
  const auto i = static_cast<std::size_t>(std::ceil(s_.render_percentile / 100.0 * double(sorted.size()))) - 1;
  return sorted[std::min(i, sorted.size() - 1)];
}

std::int64_t LatchSchedule::margin_limit() const { return std::min(margin_ns_, period_ns_ / 2); }

LatchDecision LatchSchedule::decide(std::int64_t now_ns) const {
  LatchDecision d{now_ns, 0, 0, LatchReason::Late};
  if (period_ns_ <= 0) {
    d.reason = LatchReason::NoPeriod;
  } else if (last_latch_ns_ == 0) {
    d.reason = LatchReason::NoLatch;
  } else if (now_ns - last_latch_ns_ > period_ns_ + period_ns_ / 2) {
    d.reason = LatchReason::Idle;
  } else if (!awaiting_.empty() && awaiting_.begin()->second.target_ns + s_.feedback_timeout_ns < now_ns) {
    d.reason = LatchReason::NoFeedback;
  } else if (const std::int64_t render = render_estimate_ns(); render + s_.min_margin_ns >= period_ns_) {
    d.reason = LatchReason::RenderTooLong;
  } else {
    // The first latch after now that the frame can still make with the least margin; started at
    // that latch less the render and the margin, or now with what margin is left (a render that
    // nearly fills the period squeezes it: drawn at the callback, but judged).
    const std::int64_t since = std::max<std::int64_t>(0, now_ns - last_latch_ns_);
    d.target_ns = last_latch_ns_ + (since / period_ns_ + 1) * period_ns_;
    if (d.target_ns - render - s_.min_margin_ns < now_ns) d.target_ns += period_ns_;
    d.start_ns = std::max(now_ns, d.target_ns - render - margin_limit());
    d.margin_ns = d.target_ns - render - d.start_ns;
  }
  return d;
}

}  // namespace meter::runner
