#include "meter/runner/display_latch.hpp"

namespace meter::runner {

DisplayLatch::DisplayLatch(const platform::DisplayBackend& display, LatchPacing pacing)
    : display_(display), pacing_(pacing) {}

std::int64_t DisplayLatch::wait_left_ns(std::int64_t now_ns) {
  if (!late()) return 0;
  if (!decision_) {
    schedule_.latched(display_.last_latch_ns());
    decision_ = schedule_.decide(now_ns);
  }
  return decision_->start_ns - now_ns;
}

std::int64_t DisplayLatch::starting(std::int64_t now_ns) {
  if (!late()) return 0;
  const LatchDecision d = decision_ ? *decision_ : schedule_.decide(now_ns);
  decision_.reset();
  ++reasons_[static_cast<std::size_t>(d.reason)];
  start_ns_ = now_ns;
  started_ = d;
  return d.target_ns;
}

void DisplayLatch::drawn(std::uint64_t frame, bool shown, std::int64_t now_ns) {
  if (late() && shown) schedule_.committed(frame, started_, start_ns_, now_ns);
}

void DisplayLatch::on_presented(const platform::PresentedFrame& shown) {
  schedule_.presented(shown.frame, shown.discarded, shown.presented_ns, shown.refresh_ns);
}

void DisplayLatch::summary(std::ostream& log) const {
  log << "meter-view: display pacing: --latch " << latch_pacing_name(pacing_);
  if (late()) {
    log << ": " << reasons_[0] << " frames started for a predicted latch (" << schedule_.on_time() << " made it, "
        << schedule_.missed() << " missed it by the feedback), drawn at once:";
    for (std::size_t r = 1; r < reasons_.size(); ++r)
      log << (r > 1 ? "," : "") << " " << reasons_[r] << " " << latch_reason_name(static_cast<LatchReason>(r));
    log << "; margin " << double(schedule_.margin_ns()) / 1e6 << " ms, render estimate "
        << double(schedule_.render_estimate_ns()) / 1e6 << " ms at the end";
  }
  log << "\n";
}

}  // namespace meter::runner
