#include "meter/runner/frame_trace.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "meter/protocol/trace_events.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {
namespace {

void trace_frame_events(TraceEvents& events, const engine::FrameRecord& f) {
  const engine::FrameTiming& timing = f.timing;
  const std::vector<std::pair<std::string, std::int64_t>> args = {{"frame", static_cast<std::int64_t>(f.request.frame)},
                                                                  {"drawn", timing.drawn ? 1 : 0}};
  // Overlapped (a fenced frame): the render loop's part ends at the submission; the execution is a
  // slice of the gpu lane (to when it was last seen executing); the wait for it (readback, as
  // glFinish is in the other loops) where it happened: before the next frame's submission, or
  // in the wait for input when the loop idled.
  const bool fenced = f.submitted_ns != 0;
  events.complete("evaluate", "view", f.evaluate_began_ns, f.render_began_ns, 1, args);
  events.complete("render", "view", f.render_began_ns, fenced ? f.submitted_ns : f.render_ended_ns, 1, args);
  if (fenced) {
    events.complete("execute", "view", f.submitted_ns, f.gpu_busy_until_ns, 3, args);
    events.complete("readback", "view", f.render_ended_ns - f.gpu_wait_ns, f.render_ended_ns, 1, args);
  }
  std::int64_t t = f.render_began_ns;
  const std::pair<const char*, double> parts[] = {
      {"update", timing.update_ms}, {"submit", timing.submit_ms}, {"readback", timing.gpu_readback_ms}};
  for (const auto& [name, ms] : parts) {
    if (fenced && name == std::string("readback")) continue;
    const auto end = t + static_cast<std::int64_t>(ms * 1e6);
    events.complete(name, "view", t, end, 1, args);
    t = end;
  }
}

// Args predicted_us, measured_us, units_reduced, msaa, scale_pct.
void trace_governor(TraceEvents& events, const engine::FrameRecord& f) {
  const engine::GovernorCells& c = *f.governor;
  events.complete("governor " + (c.reduced.empty() ? std::string("full quality") : c.reduced), "governor",
                  f.render_began_ns, f.render_ended_ns, 1,
                  {{"frame", static_cast<std::int64_t>(f.request.frame)},
                   {"predicted_us", std::llround(c.predicted_ms * 1000)},
                   {"measured_us", std::llround(c.measured_ms * 1000)},
                   {"units_reduced", static_cast<std::int64_t>(c.units_reduced)},
                   {"msaa", c.msaa},
                   {"scale_pct", std::llround(c.scale * 100)}});
}

}  // namespace

FrameTrace::FrameTrace(TraceEvents& events, double overrun_ms, std::ostream& log)
    : events_(events), overrun_ms_(overrun_ms), log_(log) {}

void FrameTrace::on_frame(const engine::FrameRecord& f) {
  if (events_.on()) {
    trace_frame_events(events_, f);
    if (f.governor) trace_governor(events_, f);
    if (f.timing.drawn) rendered_.emplace_back(f.request.frame, f.render_ended_ns);
    if (rendered_.size() > 64) rendered_.pop_front();  // no display, or feedback that never comes
  }
  const std::int64_t frame_ns = protocol::monotonic_now_ns() - f.evaluate_began_ns;
  if (const std::string file = events_.frame_ended(f.request.frame, frame_ns); !file.empty()) {
    protocol::LogLine(log_, protocol::LogLevel::Warning, "pipeline", {protocol::log_field("frame", static_cast<std::int64_t>(f.request.frame))}) << "meter-view: frame " << f.request.frame << " took " << frame_ns / 1'000'000 << " ms (--trace-on-overrun "
         << overrun_ms_ << "): the last seconds of trace in " << file << "\n";
  }
}

void FrameTrace::on_presented(const platform::PresentedFrame& shown) {
  while (!rendered_.empty() && rendered_.front().first < shown.frame) rendered_.pop_front();
  if (rendered_.empty() || rendered_.front().first != shown.frame) return;
  if (!shown.discarded)
    events_.complete("presented", "display", rendered_.front().second, shown.presented_ns, 1,
                     {{"frame", static_cast<std::int64_t>(shown.frame)}});
  rendered_.pop_front();
}

}  // namespace meter::runner
