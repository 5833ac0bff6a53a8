// --record FILE: what the controller publishes, as a link recording (meter/protocol/recording.hpp)
// stamped with the input's clock instead of the wall clock. Under --replay fast that clock is the
// simulated one, so the file is the drive's published state on the log's own time line: lossless
// (every tick's changes, no latest-value coalescing as on a slow link) and the same on every run.
// meter-view --play renders it on its own simulated clock; meter-linkplay replays it into a view.
//
// Lines: the header, one SNAPSHOT of every output at the model's start, then one DELTA per tick that
// changed outputs and one STATUS whenever the controller's fault flags change; `received` and `sent`
// both hold the input clock's nanoseconds.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "meter/protocol/wire.hpp"

namespace meter::controller {

class PublishRecording {
 public:
  // Empty path: off (every call is a no-op). Throws std::runtime_error when the file cannot be written.
  explicit PublishRecording(const std::string& path);
  bool on() const { return out_.is_open(); }

  void snapshot(std::int64_t t_ns, std::vector<protocol::SignalUpdate> all);
  void delta(std::int64_t t_ns, std::vector<protocol::SignalUpdate> changed);
  // Written only when `fault_flags` differs from the last one written (the first call writes 0 too).
  void status(std::int64_t t_ns, std::uint64_t frames_received, std::uint64_t frames_lost, std::uint32_t fault_flags);
  // Flushes; throws std::runtime_error naming the file on a write error.
  void close();

 private:
  void write(std::int64_t t_ns, protocol::Message message);
  std::string path_;
  std::ofstream out_;
  std::uint64_t sequence_ = 0;
  bool status_written_ = false;
  std::uint32_t last_faults_ = 0;
};

}  // namespace meter::controller
