// --trace: when link updates were applied and when each frame was rendered and written, on
// CLOCK_REALTIME (the clock of the controller's trace and of SocketCAN's kernel timestamps), so
// bench/latency can split a CAN frame's way to the PNG by stage. Rows after the header
// "event,t_ns,a,b,c":
//   a,<t_ns>,<sender monotonic ns>,<sequence>      a poll applied changes (newest frame's stamp)
//   r,<t_ns update>,<frame>,<t_ns rendered>          frame drawn and read back
//   w,<t_ns>,<frame>                                 its PNG written (writer thread)
//   p,<t_ns>,<frame>                                 it turned into light on the display (--output:
//                                                    the compositor's presentation feedback)
#pragma once

#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/runner/presentation_listener.hpp"

namespace meter::runner {

// A frame sink: the "r" row of every frame; with a display, the "p" row of every frame shown.
class LatencyTrace : public engine::FrameSink, public PresentationListener {
 public:
  // An empty path: no trace (every call does nothing).
  explicit LatencyTrace(const std::string& path);

  // CLOCK_REALTIME in nanoseconds.
  static std::int64_t now();

  // Rows come from the render loop and from the PNG writer thread.
  void applied(std::int64_t sender_ns, std::uint64_t seq);
  void frame(std::uint64_t n, std::int64_t t_update, std::int64_t t_rendered);
  void png_written(std::uint64_t n);
  void on_frame(const engine::FrameRecord& f) override {
    frame(f.request.frame, f.evaluate_began_realtime_ns, f.render_ended_realtime_ns);
  }
  void on_presented(const platform::PresentedFrame& shown) override;

 private:
  std::mutex mutex_;
  std::ofstream out_;
};

}  // namespace meter::runner
