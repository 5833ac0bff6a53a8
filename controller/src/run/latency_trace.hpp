#pragma once

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/controller/input/can_frame.hpp"
#include "meter/controller/input/clocks.hpp"

namespace meter::controller {

// --trace: one CSV line per pipeline event, so the time from a frame's kernel receive timestamp to
// the link can be split by stage offline (bench/latency). Rows:
//   f,<t_ns>,<frame_ts_ns>,<can id>             the model has decoded the frame (ts: kernel stamp on can:)
//   p,<t_ns>,<signal id>,<value>                a changed output handed to the publisher
//   s,<t_ns>,<bytes sent total>,<deltas total>  the link wrote bytes to the socket
//   c,<t_ns>,<CLOCK_MONOTONIC ns>,              once: maps the link's send stamps onto t_ns
//   h,<t_ns>,<what>,<value>                     a health counter changed: bus_state (0 error-active,
//                                               1 warning, 2 passive, 3 bus-off), error_frames,
//                                               kernel_drops, interface_drops, replay_slips,
//                                               deferred_polls, view_faults
// Buffered in memory-sized blocks: the controller's loop must not wait for a disk (or a 9p share).
class Trace {
 public:
  explicit Trace(const std::string& path) {
    if (path.empty()) return;
    out_.rdbuf()->pubsetbuf(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    out_.open(path);
    if (!out_) throw std::runtime_error(path + ": cannot write the trace");
    out_ << "event,t_ns,a,b\n";
    // The link's frames carry CLOCK_MONOTONIC send stamps: this pair maps them onto the trace.
    out_ << "c," << realtime_ns() << "," << monotonic_ns() << ",\n";
  }
  bool on() const { return out_.is_open(); }
  void frame(const CanFrame& f) {
    if (on()) out_ << "f," << realtime_ns() << "," << f.timestamp_ns << "," << f.id << "\n";
  }
  void publish(int id, double v) {
    if (on()) out_ << "p," << realtime_ns() << "," << id << "," << fmt(v) << "\n";
  }
  void sent(std::uint64_t bytes, std::uint64_t deltas) {
    if (on()) out_ << "s," << realtime_ns() << "," << bytes << "," << deltas << "\n";
  }
  void health(const char* what, std::uint64_t value) {
    if (on()) out_ << "h," << realtime_ns() << "," << what << "," << value << "\n";
  }
  void flush() {
    if (on()) out_.flush();
  }

 private:
  static std::string fmt(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
  }
  std::vector<char> buf_ = std::vector<char>(1 << 20);
  std::ofstream out_;
};

}  // namespace meter::controller
