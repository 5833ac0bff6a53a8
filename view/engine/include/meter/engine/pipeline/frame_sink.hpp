// What the frame pipeline hands on after each frame, and the one interface its observers and
// outputs implement (meter-view's timing CSV, latency trace, trace-json slices, integrity monitor,
// PNG dump with its frames.csv rows; a display next). A new sink is its own file and one
// FramePipeline::add_sink call in the mode that uses it.
#pragma once

#include <cstdint>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/pipeline/frame_governor.hpp"
#include "meter/engine/renderer.hpp"

namespace meter::engine {

// What a mode asks of one frame (its policy decides when a frame is due and which one it is).
struct FrameRequest {
  std::uint64_t frame = 0;    // the mode's frame number (frames.csv frame)
  double t = 0.0;             // seconds on the mode's clock (frames.csv time_s)
  bool force = false;         // drawn even when nothing changed
  bool read = false;          // read back into Renderer::last_image() by the render itself
  bool output = false;        // a sink writes this frame out (the PNG dump)
  bool output_asked = false;  // asked for (--dump-at, SIGUSR1), not periodic: never dropped
};

// One frame as drawn (or skipped), with the state it was drawn from.
struct FrameRecord {
  FrameRequest request;
  bool link_up = true;
  FrameTiming timing;
  const std::vector<BindingState>* states = nullptr;  // each binding as drawn
  const GovernorCells* governor = nullptr;            // nullptr: no governor
  // CLOCK_MONOTONIC (trace-json, as the link's stamps): evaluation began, render began and ended.
  std::int64_t evaluate_began_ns = 0, render_began_ns = 0, render_ended_ns = 0;
  // The overlapped pipeline (FramePipeline::set_overlap), CLOCK_MONOTONIC: GL submission began and
  // ended (the frame fenced); it was last seen executing at gpu_busy_until_ns (when a wait for it
  // ended, or the last check that found its fence unsignalled: a lower bound of when it finished)
  // and the GL thread waited gpu_wait_ns for it. render_ended_ns is when it was first seen drawn.
  std::int64_t draw_began_ns = 0, submitted_ns = 0, gpu_busy_until_ns = 0, gpu_wait_ns = 0;
  // CLOCK_REALTIME (the latency trace's): evaluation began, render ended.
  std::int64_t evaluate_began_realtime_ns = 0, render_ended_realtime_ns = 0;
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Before frame `frame` is planned (the integrity monitor names the boxes it will read).
  virtual void before_frame(std::uint64_t /*frame*/) {}
  // The frame just drawn, before any sink's on_frame: what is read here is the frame as drawn,
  // before a check may repaint part of it (a concurrent read-back is issued here).
  virtual void on_drawn(const FrameRecord& /*frame*/) {}
  // Every frame, drawn or skipped, in the order the sinks were added.
  virtual void on_frame(const FrameRecord& frame) = 0;
  // The mode ends: what is pending is written.
  virtual void finish() {}
};

}  // namespace meter::engine
