// The integrity monitor as a sink of meter-view's live frame pipeline: the injected test fault
// (--inject-fault), the check after each frame, the fault raised in STATUS (kViewFaultIntegrity)
// within the frame, the rate-limited log and the frames.csv cells. Docs: docs/integrity.md.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "meter/engine/integrity/fault_injection.hpp"
#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/integrity_monitor.hpp"
#include "meter/runner/render_context.hpp"
#include "meter/runner/view_health.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

// --inject-fault KIND[:REGION]@FIRST[-LAST]: KIND as engine::parse_fault_kind, or "display" (the
// display's copy of those frames is lost: the back buffer keeps what it held and is not shown),
// REGION a safety region's name (every kind but stuck and display needs one), frames FIRST..LAST
// (the live loop's numbers; no LAST: to the end).
struct FaultSchedule {
  engine::FaultInjection fault;
  bool display_copy_lost = false;  // "display": a fault of the display path, not of the renderer
  std::uint64_t first = 0;
  std::optional<std::uint64_t> last;
};
// Throws ViewError naming the option, the text and what was expected.
FaultSchedule parse_fault_schedule(const std::string& text, const engine::Scene& scene, int height);

// Log lines of faults: the first of each region always, then at most one line per second; the
// ones left out are counted.
class FaultLogLimit {
 public:
  using Clock = std::chrono::steady_clock;
  bool admit(const std::string& region, Clock::time_point now);
  std::uint64_t suppressed() const { return suppressed_; }

 private:
  std::vector<std::string> seen_;
  std::optional<Clock::time_point> last_;
  std::uint64_t suppressed_ = 0;
};

class IntegrityStage : public engine::FrameSink {
 public:
  using Clock = std::chrono::steady_clock;
  // Logs whether the monitor is on (and why not) and any injected fault. Faults are reported to
  // `health` (which outlives the stage).
  IntegrityStage(RenderContext& ctx, const ViewOptions& options, ViewHealth& health, std::ostream& log);
  bool on() const { return monitor_.on(); }
  // Before frame `frame` renders: the monitor names the boxes it will read (IntegrityMonitor::
  // prepare); the injected fault starts or ends.
  void before_frame(std::uint64_t frame) override;
  // After the frame rendered: checks it; a fault is logged and reported to the constructor's health.
  // Not with a display (watch_display): the display's sink checks the frame it is about to show.
  void on_frame(const engine::FrameRecord& frame) override {
    if (!on_display_) after_frame(frame.request.frame, Clock::now(), nullptr);
  }
  // With a display: its sink calls check_shown() with the back buffer the frame was copied into,
  // before it is shown; the monitor's boxes are not resolved with the frame (the frame's own
  // resolve and copy fill what is read).
  void watch_display() { on_display_ = true; }
  void check_shown(const engine::FrameRecord& frame, const RegionReader& reader) {
    after_frame(frame.request.frame, Clock::now(), &reader);
  }
  // Test only (--inject-fault display@...): the display's copy of `frame` is lost.
  bool display_copy_lost(std::uint64_t frame) const {
    return schedule_ && schedule_->display_copy_lost && frame >= schedule_->first &&
           (!schedule_->last || frame <= *schedule_->last);
  }
  // The frames.csv cells of the frame last checked (nullptr when the monitor is off).
  const IntegrityCells* cells() const { return monitor_.on() ? &cells_ : nullptr; }
  void summary(std::ostream& log) const;
  const IntegrityMonitor& monitor() const { return monitor_; }

 private:
  void after_frame(std::uint64_t frame, Clock::time_point now, const RegionReader* reader);

  RenderContext& ctx_;
  ViewHealth& health_;
  std::ostream& log_;
  IntegrityMonitor monitor_;
  std::optional<FaultSchedule> schedule_;
  IntegrityCells cells_;
  FaultLogLimit limit_;
  std::optional<std::uint64_t> first_fault_frame_;
  bool on_display_ = false;
};

}  // namespace meter::runner
