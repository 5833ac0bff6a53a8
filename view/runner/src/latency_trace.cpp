#include "meter/runner/latency_trace.hpp"

#include "meter/protocol/trace_events.hpp"

#include "output_file.hpp"

namespace meter::runner {

LatencyTrace::LatencyTrace(const std::string& path) {
  if (path.empty()) return;
  out_ = create_output_file(path, "cannot write the trace");
  out_ << "event,t_ns,a,b,c\n";
}

std::int64_t LatencyTrace::now() { return protocol::realtime_now_ns(); }

void LatencyTrace::applied(std::int64_t sender_ns, std::uint64_t seq) {
  if (!out_.is_open()) return;
  std::lock_guard lock(mutex_);
  out_ << "a," << now() << "," << sender_ns << "," << seq << "\n";
}

void LatencyTrace::frame(std::uint64_t n, std::int64_t t_update, std::int64_t t_rendered) {
  if (!out_.is_open()) return;
  std::lock_guard lock(mutex_);
  out_ << "r," << t_update << "," << n << "," << t_rendered << "\n";
}

void LatencyTrace::png_written(std::uint64_t n) {
  if (!out_.is_open()) return;
  std::lock_guard lock(mutex_);
  out_ << "w," << now() << "," << n << "\n";
}

void LatencyTrace::on_presented(const platform::PresentedFrame& shown) {
  if (!out_.is_open() || shown.discarded) return;
  // The feedback is on CLOCK_MONOTONIC; this trace's clock is CLOCK_REALTIME.
  const std::int64_t t = shown.presented_ns - protocol::monotonic_now_ns() + now();
  std::lock_guard lock(mutex_);
  out_ << "p," << t << "," << shown.frame << "\n";
}

}  // namespace meter::runner
