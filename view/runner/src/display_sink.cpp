#include "meter/runner/display_sink.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "meter/platform/display_damage.hpp"
#include "meter/runner/process_signals.hpp"
#include "meter/protocol/trace_events.hpp"
#include "meter/protocol/log/logger.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::runner {

DisplaySink::DisplaySink(RenderContext& ctx, std::ostream& log) : ctx_(ctx), log_(log) {
  if (!ctx_.display) throw std::invalid_argument("DisplaySink: the render context has no display");
}

void DisplaySink::on_frame(const engine::FrameRecord& frame) {
  const std::uint64_t n = frame.request.frame;
  std::vector<platform::PixelRegion> damage = ctx_.renderer.take_written(engine::Renderer::WrittenReader::Display);
  // Test only: a lost copy keeps the back buffer as it stood; its damage goes with the next copy.
  const bool lost = integrity_ && integrity_->display_copy_lost(n);
  if (lost) lost_.insert(lost_.end(), damage.begin(), damage.end());
  if (!lost && !lost_.empty()) {
    damage.insert(damage.end(), lost_.begin(), lost_.end());
    lost_.clear();
  }
  const std::int64_t began = protocol::monotonic_now_ns();
  // The frame goes into the back buffer once: for its damage, or for the monitor's first read (a
  // frame that drew nothing is shown again so that what the monitor judged is what is shown).
  bool copied = false, tried = lost;
  double copy_ms = 0.0;
  const auto copy = [&] {
    if (!std::exchange(tried, true)) {
      const std::int64_t t = protocol::monotonic_now_ns();
      copied = ctx_.display->copy(ctx_.renderer.resolved_target(), damage);
      copy_ms += double(protocol::monotonic_now_ns() - t) / 1e6;
    }
    return copied || lost;
  };
  if (!damage.empty()) copy();
  if (integrity_) check(frame, copy, copied, copy_ms);
  if (copied) {
    const std::uint64_t copied_before = summary_.pixels_copied;
    summary_.pixels_copied = ctx_.display->pixels_copied();
    ctx_.display->show(n);
    if (frame.render_ended_ns) summary_.after_render_ms += double(began - frame.render_ended_ns) / 1e6;
    ++summary_.presents;
    summary_.pixels_damaged += static_cast<std::uint64_t>(platform::area(damage));
    last_frame_ = n;
    summary_.present_ms += double(protocol::monotonic_now_ns() - began) / 1e6;
    if (log_each_frame_) {
      const auto& target = ctx_.renderer.resolved_target();
      log_ << "meter-view: display: frame " << n << " shown: copied " << summary_.pixels_copied - copied_before
           << " pixels of the frame's " << std::int64_t(target.width()) * target.height() << " (" << platform::area(damage)
           << " damaged)\n";
    }
  } else {
    for (PresentationListener* l : listeners_) l->not_presented(n);
  }
  note_stalls(n);
  take(0);
}

// The integrity monitor judges the regions read back from the back buffer the frame was copied
// into; its safe-path repaints are copied after it, before the buffer is shown.
void DisplaySink::check(const engine::FrameRecord& frame, const std::function<bool()>& copy, const bool& copied,
                        double& copy_ms) {
  const std::int64_t began = protocol::monotonic_now_ns();
  const double copy_before = copy_ms;
  integrity_->check_shown(frame, [&](std::span<const platform::PixelRegion> boxes) {
    if (!copy()) return std::vector<platform::Image>(boxes.size());
    // The reads wait for the copy (and the frame's resolve) to finish, as the swap would: that wait
    // is timed apart, so monitor_ms is the monitor's own reads, judgement and repairs.
    const std::int64_t t = protocol::monotonic_now_ns();
    ctx_.display->gl().Finish();
    copy_ms += double(protocol::monotonic_now_ns() - t) / 1e6;
    return ctx_.display->read_shown(boxes);
  });
  if (copied) {
    const auto repaired = ctx_.renderer.take_written(engine::Renderer::WrittenReader::Display);
    if (!repaired.empty()) ctx_.display->copy_more(ctx_.renderer.resolved_target(), repaired);
  }
  summary_.monitor_ms += double(protocol::monotonic_now_ns() - began) / 1e6 - (copy_ms - copy_before);
  ++summary_.monitored;
}

// A frame callback or page flip that did not come: the display froze (counted, the first logged,
// each reported as a fault in STATUS).
void DisplaySink::note_stalls(std::uint64_t frame) {
  const std::uint64_t stalls = ctx_.display->stalls();
  if (stalls <= summary_.stalls) return;
  if (summary_.stalls == 0)
    protocol::LogLine(log_, protocol::LogLevel::Warning, "display", {protocol::log_field("frame", static_cast<std::int64_t>(frame))})
        << "meter-view: display: frame " << frame << ": the previous frame was never shown within the wait (no frame callback or page flip): frozen display\n";
  summary_.stalls = stalls;
  if (health_) health_->report(protocol::kViewFaultDisplayFrozen, ViewHealth::Clock::now());
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
       << summary_.present_ms / double(std::max<std::uint64_t>(1, summary_.presents)) << " ms in present";
  if (summary_.monitored)
    log_ << "; the integrity monitor on the shown buffer " << summary_.monitor_ms / double(summary_.monitored)
         << " ms per frame (" << summary_.monitored << " frames)";
  log_ << "\n";
}

void DisplaySink::hold(double seconds, std::ostream& log) {
  install_stop_handlers();
  log << "meter-view: frame " << last_frame_.value_or(0) << " on the display; holding it "
      << (seconds > 0 ? std::to_string(seconds) + " s" : std::string("until SIGINT/SIGTERM")) << std::endl;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!stop_requested() && (seconds <= 0 || std::chrono::steady_clock::now() < until)) {
    ctx_.display->take_presented(50);  // reads the display's events: a lost display throws
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
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
