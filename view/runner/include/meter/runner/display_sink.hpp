// --output wayland|drm: the frame pipeline's display. After every frame that wrote pixels, the
// renderer's resolved target is copied into the display's back buffer with the boxes written since
// the last copy; with the integrity monitor (live), the monitor then reads its regions back from
// that buffer, judges them, and its safe-path repaints are copied too; then the buffer is shown.
// The presentation feedback (when each frame turned into light) reaches the PresentationListeners
// (the timing CSV, frames.csv, the trace) as it arrives; a frame callback or page flip that does
// not come is a frozen display, reported to the view's health (STATUS).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <vector>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/platform/display.hpp"
#include "meter/runner/integrity_stage.hpp"
#include "meter/runner/presentation_listener.hpp"
#include "meter/runner/render_context.hpp"
#include "meter/runner/view_health.hpp"

namespace meter::runner {

// What a run's presentation feedback adds up to (the summary line, the benchmarks).
struct PresentationSummary {
  std::uint64_t presents = 0, presented = 0, discarded = 0, stalls = 0;
  std::uint64_t pixels_copied = 0, pixels_damaged = 0;
  std::uint32_t refresh_ns = 0;
  // Per presented frame, summed: from the render's end to the copy (the sinks before the display:
  // the integrity monitor's reads, the dump's, the CSVs) and the present itself (the wait for the
  // previous frame's callback or flip, the copy, the monitor, the swap).
  double after_render_ms = 0.0, present_ms = 0.0;
  // The integrity monitor on the shown buffer: its reads, judgement and repairs, summed over the
  // frames it was asked to check.
  double monitor_ms = 0.0;
  std::uint64_t monitored = 0;
  std::int64_t first_presented_ns = 0;  // CLOCK_MONOTONIC; 0: none yet
  // Presented frames shown more than one refresh period after the one before (a refresh without a
  // new frame while one was due).
  std::uint64_t shown_late = 0;
};

class DisplaySink : public engine::FrameSink {
 public:
  // ctx.display must be set (RenderContext opens it for --output).
  DisplaySink(RenderContext& ctx, std::ostream& log);
  void add_listener(PresentationListener& listener) { listeners_.push_back(&listener); }
  // The monitor judges each frame in the back buffer before it is shown (live).
  void check_with(IntegrityStage& integrity) {
    integrity_ = &integrity;
    integrity.watch_display();
  }
  // A frozen display is reported there (kViewFaultDisplayFrozen).
  void report_to(ViewHealth& health) { health_ = &health; }
  // One log line per frame shown: the pixels copied into its buffer against the frame's and its
  // damage (how partial the redraw stayed on the display; --info).
  void log_each_frame() { log_each_frame_ = true; }

  void on_frame(const engine::FrameRecord& frame) override;
  // Waits (at most 1 s) for the feedback of the frames presented, tells the listeners, logs the
  // summary.
  void finish() override;

  // After finish(): the frame last shown stays on the display for `seconds` (0: until SIGINT/
  // SIGTERM), the display's events read every 50 ms: a display that went away throws
  // platform::DisplayLost.
  void hold(double seconds, std::ostream& log);

  const PresentationSummary& summary() const { return summary_; }
  // The frame last presented (shown, or still queued), or nullopt before the first present.
  std::optional<std::uint64_t> last_presented_frame() const { return last_frame_; }

 private:
  void take(int wait_ms);
  void check(const engine::FrameRecord& frame, const std::function<bool()>& copy, const bool& copied, double& copy_ms);
  void note_stalls(std::uint64_t frame);

  RenderContext& ctx_;
  std::ostream& log_;
  std::vector<PresentationListener*> listeners_;
  PresentationSummary summary_;
  std::optional<std::uint64_t> last_frame_;
  std::int64_t last_shown_ns_ = 0;
  std::uint64_t last_sequence_ = 0;
  bool finished_ = false;
  bool log_each_frame_ = false;
  IntegrityStage* integrity_ = nullptr;
  ViewHealth* health_ = nullptr;
  std::vector<platform::PixelRegion> lost_;  // test only: damage of copies an injected fault lost
};

}  // namespace meter::runner
