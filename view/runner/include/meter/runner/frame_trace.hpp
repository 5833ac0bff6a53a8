// --trace-json's slices of each frame as a frame sink (docs/tracing.md): evaluate (bindings,
// outputs applied), render, and inside render the renderer's measured parts laid end to end
// (update, submit, readback); with the frame-rate governor on, a "governor <units below full |
// full quality>" slice over the render span. Then --trace-on-overrun: a frame that took longer
// than its limit writes the last seconds of trace (logged with the file's name). With a display
// (--output), a "presented" slice (category display) from each shown frame's render end to the
// time it turned into light.
#pragma once

#include <cstdint>
#include <deque>
#include <ostream>
#include <utility>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/runner/presentation_listener.hpp"
#include "meter/runner/trace_ring.hpp"

namespace meter::runner {

class FrameTrace : public engine::FrameSink, public PresentationListener {
 public:
  // `events` and `log` outlive the sink; `overrun_ms` is --trace-on-overrun's (for the log line).
  FrameTrace(TraceEvents& events, double overrun_ms, std::ostream& log);
  void on_frame(const engine::FrameRecord& frame) override;
  void on_presented(const platform::PresentedFrame& shown) override;

 private:
  TraceEvents& events_;
  double overrun_ms_;
  std::ostream& log_;
  std::deque<std::pair<std::uint64_t, std::int64_t>> rendered_;  // frame, render end: awaiting feedback
};

}  // namespace meter::runner
