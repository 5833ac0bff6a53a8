#include "meter/runner/display_sink.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "meter/platform/display_damage.hpp"
#include "meter/protocol/trace_events.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {

DisplaySink::DisplaySink(RenderContext& ctx, std::ostream& log) : ctx_(ctx), log_(log) {
  if (!ctx_.display) throw std::invalid_argument("DisplaySink: the render context has no display");
}

void DisplaySink::on_frame(const engine::FrameRecord& frame) {
  const auto damage = ctx_.renderer.take_written(engine::Renderer::WrittenReader::Display);
  if (!damage.empty()) {
    const std::int64_t began = protocol::monotonic_now_ns();
    if (frame.render_ended_ns) summary_.after_render_ms += double(began - frame.render_ended_ns) / 1e6;
    ctx_.display->present(ctx_.renderer.resolved_target(), damage, frame.request.frame);
    summary_.present_ms += double(protocol::monotonic_now_ns() - began) / 1e6;
    // A frame callback or page flip that did not come: the display froze (counted, first logged).
    if (const std::uint64_t stalls = ctx_.display->stalls(); stalls > summary_.stalls) {
      if (summary_.stalls == 0)
        protocol::LogLine(log_, protocol::LogLevel::Warning, "display", {protocol::log_field("frame", static_cast<std::int64_t>(frame.request.frame))}) << "meter-view: display: frame " << frame.request.frame
             << ": the previous frame was never shown within the wait (no frame callback or page flip): frozen display\n";
      summary_.stalls = stalls;
    }
    ++summary_.presents;
    summary_.pixels_damaged += static_cast<std::uint64_t>(platform::area(damage));
    last_frame_ = frame.request.frame;
  }
  take(0);
}

void DisplaySink::finish() {
  if (finished_) return;
  finished_ = true;
  take(1000);
  summary_.stalls = ctx_.display->stalls();
  summary_.pixels_copied = ctx_.display->pixels_copied();
  for (PresentationListener* l : listeners_) l->presentation_done();
  log_ << "meter-view: display: " << summary_.presents << " frames presented, " << summary_.presented
       << " shown, " << summary_.discarded << " discarded, " << summary_.shown_late << " shown later than the next refresh, "
       << summary_.stalls << " stalls (a frame callback or page flip that did not come); refresh " << summary_.refresh_ns / 1e6 << " ms; copied "
       << summary_.pixels_copied << " pixels for " << summary_.pixels_damaged << " damaged; per frame "
       << summary_.after_render_ms / double(std::max<std::uint64_t>(1, summary_.presents)) << " ms from render end to the copy, "
       << summary_.present_ms / double(std::max<std::uint64_t>(1, summary_.presents)) << " ms in present\n";
}

void DisplaySink::take(int wait_ms) {
  for (const platform::PresentedFrame& shown : ctx_.display->take_presented(wait_ms)) {
    if (shown.discarded) {
      ++summary_.discarded;
    } else {
      ++summary_.presented;
      if (shown.refresh_ns) summary_.refresh_ns = shown.refresh_ns;
      if (summary_.first_presented_ns == 0) summary_.first_presented_ns = shown.presented_ns;
      // The refresh counter where the compositor keeps one, else the time over the period.
      if (last_shown_ns_ != 0 && (last_sequence_ || shown.sequence))
        summary_.shown_late += shown.sequence - last_sequence_ > 1;
      else if (last_shown_ns_ != 0 && shown.refresh_ns)
        summary_.shown_late += std::llround(double(shown.presented_ns - last_shown_ns_) / shown.refresh_ns) > 1;
      last_shown_ns_ = shown.presented_ns;
      last_sequence_ = shown.sequence;
    }
    for (PresentationListener* l : listeners_) l->on_presented(shown);
  }
}

}  // namespace meter::runner
