// --trace-json: Chrome trace-event JSON (the "JSON Object Format" that Perfetto UI and
// chrome://tracing open) written by meter-controller and meter-view alike, so one CAN frame can be
// followed from its receipt through decode and publish, across the link, to evaluation, render,
// readback and PNG encode. Complete events ("ph":"X") with ts/dur in microseconds on
// CLOCK_MONOTONIC, the clock of the link's sender stamps: both processes' files share one time
// base and can be loaded side by side (or concatenated).
#pragma once

#include <chrono>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace meter::protocol {

// CLOCK_MONOTONIC in ns (std::chrono::steady_clock is the same clock on Linux).
std::int64_t monotonic_now_ns();
std::int64_t monotonic_ns(std::chrono::steady_clock::time_point t);
// CLOCK_REALTIME in ns: the clock of SocketCAN's kernel receive stamps, so the controller's and the
// view's --trace CSVs (bench/latency) compare with the bus's own times.
std::int64_t realtime_now_ns();

struct TraceEvent {
  std::string name;
  std::string category;
  std::int64_t begin_ns = 0;  // CLOCK_MONOTONIC
  std::int64_t end_ns = 0;    // >= begin_ns
  int pid = 0;
  int tid = 0;
  std::vector<std::pair<std::string, std::int64_t>> args;  // integer arguments shown with the slice
};

// One event as a JSON object: {"name":..,"cat":..,"ph":"X","ts":..,"dur":..,"pid":..,"tid":..,"args":{..}},
// ts and dur in microseconds with 3 decimals (exact nanoseconds). Pure.
std::string format_trace_event(const TraceEvent& event);
// A metadata event naming a process or thread ("process_name" / "thread_name"). Pure.
std::string format_trace_name(std::string_view kind, int pid, int tid, std::string_view name);
// `text` as a JSON string literal.
std::string json_quoted(std::string_view text);

// Appends events to a file as they happen (buffered; the closing bracket is written by close() or
// the destructor). Thread-safe. An empty path: off, every call is a no-op.
class TraceEventFile {
 public:
  // Throws std::runtime_error naming the file when it cannot be written.
  TraceEventFile(const std::string& path, std::string_view process_name);
  ~TraceEventFile();
  TraceEventFile(const TraceEventFile&) = delete;
  TraceEventFile& operator=(const TraceEventFile&) = delete;

  bool on() const { return on_; }
  void thread_name(int tid, std::string_view name);
  void complete(std::string_view name, std::string_view category, std::int64_t begin_ns, std::int64_t end_ns,
                int tid = 1, std::vector<std::pair<std::string, std::int64_t>> args = {});
  // Finishes the JSON document. Idempotent; false if a write failed.
  bool close();

 private:
  void append(const std::string& object);  // mutex_ held

  bool on_ = false;
  int pid_ = 0;
  bool first_ = true;
  std::mutex mutex_;
  std::vector<char> buffer_;
  std::ofstream out_;
};

}  // namespace meter::protocol
