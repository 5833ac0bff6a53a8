#include "meter/runner/trace_ring.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "meter/runner/view_error.hpp"

namespace meter::runner {

TraceRing::TraceRing(std::int64_t keep_ns, std::size_t max_events) : keep_ns_(keep_ns), max_(max_events) {}

void TraceRing::add(protocol::TraceEvent event) {
  const std::int64_t newest = event.end_ns;
  events_.push_back(std::move(event));
  while (events_.size() > max_ || (!events_.empty() && events_.front().end_ns < newest - keep_ns_)) events_.pop_front();
}

std::vector<protocol::TraceEvent> TraceRing::events() const { return {events_.begin(), events_.end()}; }

std::string trace_document(std::string_view process_name, int pid, const std::vector<std::pair<int, std::string>>& threads,
                           const std::vector<protocol::TraceEvent>& events) {
  std::string out = "{\"displayTimeUnit\":\"ms\",\"otherData\":{\"clock\":\"CLOCK_MONOTONIC\"},\"traceEvents\":[\n";
  out += protocol::format_trace_name("process_name", pid, 0, process_name);
  for (const auto& [tid, name] : threads) out += ",\n" + protocol::format_trace_name("thread_name", pid, tid, name);
  for (const auto& e : events) out += ",\n" + protocol::format_trace_event(e);
  return out + "\n]}\n";
}

TraceEvents::TraceEvents(const std::string& json_path, double overrun_ms, std::filesystem::path overrun_dir)
    : file_(json_path, "meter-view"),
      ring_on_(overrun_ms > 0),
      overrun_ns_(static_cast<std::int64_t>(overrun_ms * 1e6)),
      dir_(std::move(overrun_dir)) {}

void TraceEvents::thread_name(int tid, std::string_view name) {
  file_.thread_name(tid, name);
  std::lock_guard lock(mutex_);
  threads_.emplace_back(tid, std::string(name));
}

void TraceEvents::complete(std::string_view name, std::string_view category, std::int64_t begin_ns,
                           std::int64_t end_ns, int tid, std::vector<std::pair<std::string, std::int64_t>> args) {
  if (!ring_on_) {
    file_.complete(name, category, begin_ns, end_ns, tid, std::move(args));
    return;
  }
  file_.complete(name, category, begin_ns, end_ns, tid, args);
  std::lock_guard lock(mutex_);
  ring_.add(protocol::TraceEvent{std::string(name), std::string(category), begin_ns, end_ns,
                                 static_cast<int>(::getpid()), tid, std::move(args)});
}

std::string TraceEvents::frame_ended(std::uint64_t frame, std::int64_t frame_ns) {
  if (!ring_on_ || frame_ns <= overrun_ns_) return {};
  const std::int64_t now = protocol::monotonic_now_ns();
  std::string text;
  {
    std::lock_guard lock(mutex_);
    if (overrun_files_ > 0 && now - last_written_ns_ < kRingNs) return {};
    last_written_ns_ = now;
    text = trace_document("meter-view", static_cast<int>(::getpid()), threads_, ring_.events());
  }
  char name[48];
  std::snprintf(name, sizeof name, "overrun_%06llu.json", static_cast<unsigned long long>(frame));
  const auto path = dir_ / name;
  std::ofstream out(path);
  out << text;
  if (!out) throw ViewError(path.string() + ": cannot write the overrun trace");
  ++overrun_files_;
  return path.string();
}

}  // namespace meter::runner
