// --trace-on-overrun MS: the view's trace-event slices kept in memory for the last few seconds
// (a ring bounded by time and by count) and written as a Chrome trace-event file when a frame runs
// over MS, as Kanzi's profiler does: a slow frame is caught with what led up to it, without
// writing a trace all the time. TraceEvents is what the live loop emits slices to: the
// --trace-json file, the ring, both or neither.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "meter/protocol/trace_events.hpp"

namespace meter::runner {

class TraceRing {
 public:
  // Keeps events that ended within `keep_ns` of the newest one, at most `max_events`.
  TraceRing(std::int64_t keep_ns, std::size_t max_events);
  void add(protocol::TraceEvent event);
  // The events held, oldest end first.
  std::vector<protocol::TraceEvent> events() const;

 private:
  std::int64_t keep_ns_;
  std::size_t max_;
  std::deque<protocol::TraceEvent> events_;
};

// A whole trace-event document (the --trace-json format) of `events` with process and thread
// names. Pure.
std::string trace_document(std::string_view process_name, int pid, const std::vector<std::pair<int, std::string>>& threads,
                           const std::vector<protocol::TraceEvent>& events);

class TraceEvents {
 public:
  static constexpr std::int64_t kRingNs = 5'000'000'000;  // the last 5 s
  static constexpr std::size_t kRingEvents = 100'000;      // ~20 ms of slices per frame at 240 fps: far above

  // json_path empty: no file; overrun_ms <= 0: no ring. Throws (std::runtime_error) when the file
  // cannot be written.
  TraceEvents(const std::string& json_path, double overrun_ms, std::filesystem::path overrun_dir);
  bool on() const { return file_.on() || ring_on_; }
  void thread_name(int tid, std::string_view name);
  void complete(std::string_view name, std::string_view category, std::int64_t begin_ns, std::int64_t end_ns,
                int tid = 1, std::vector<std::pair<std::string, std::int64_t>> args = {});
  // A frame of `frame_ns` ended: over the threshold, the ring is written to
  // <overrun_dir>/overrun_<frame>.json (at most one file per ring length, so a view that overruns
  // every frame does not write every frame) and the file's path returned; "" otherwise.
  std::string frame_ended(std::uint64_t frame, std::int64_t frame_ns);
  std::uint64_t overrun_files() const { return overrun_files_; }
  bool close() { return file_.close(); }

 private:
  protocol::TraceEventFile file_;
  bool ring_on_ = false;
  std::int64_t overrun_ns_ = 0;
  std::filesystem::path dir_;
  std::mutex mutex_;  // ring_, threads_
  TraceRing ring_{kRingNs, kRingEvents};
  std::vector<std::pair<int, std::string>> threads_;
  std::int64_t last_written_ns_ = 0;
  std::uint64_t overrun_files_ = 0;
};

}  // namespace meter::runner
