// The PNG dump as a frame sink (--dump-every, --dump-at, SIGUSR1, --dump-last): each frame the
// mode asks to output goes to the PNG writer thread, its frames.csv row written when the writer
// takes it (a dropped frame leaves no row naming a missing PNG). Sequential: the frame the render
// read back itself (Renderer::last_image()), rows top-down. Concurrent: read through pixel-pack
// buffers, issued as soon as the frame is drawn (before the integrity monitor may repaint part of
// it), handed to the writer once the fence has signalled (rows bottom-up, flipped by the writer).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/integrity_stage.hpp"
#include "meter/runner/pixel_pack_readback.hpp"
#include "meter/runner/png_writer.hpp"
#include "meter/runner/render_context.hpp"
#include "meter/runner/stage_meter.hpp"
#include "meter/runner/trace_ring.hpp"

namespace meter::runner {

struct FrameDumpSetup {
  bool concurrent = false;                       // read through pixel-pack buffers
  DumpOverflow overflow = DumpOverflow::Block;   // a periodic dump's; asked-for dumps always block
  const IntegrityStage* integrity = nullptr;     // its cells in each row (nullptr: none)
  StageMeter* readback = nullptr;                // live --stats: the readback stage (nullptr: none; needed when concurrent)
  TraceEvents* events = nullptr;                 // waits for output space as slices (nullptr: none)
  std::function<void()> while_full;              // done while the writer's buffer is full
  std::chrono::nanoseconds slow_readback{0};     // test only (--inject-slow-stage readback): slept per read
};

class FrameDump : public engine::FrameSink {
 public:
  // `writer` and `csv` outlive the dump. The GL context must be current. Throws
  // std::invalid_argument for a concurrent dump without the readback stage's meter.
  FrameDump(RenderContext& ctx, PngWriter& writer, FramesCsv& csv, FrameDumpSetup setup);

  bool asynchronous() const { return readback_.asynchronous(); }
  void on_drawn(const engine::FrameRecord& frame) override;
  void on_frame(const engine::FrameRecord& frame) override;
  // Every read in flight collected and handed to the writer.
  void finish() override;
  // --dump-last: the frame that stands, read now, as frame `n` at `t` (drawn = false).
  void dump_standing(std::uint64_t n, double t, bool link_up);
  // Concurrent: hands every finished read to the writer; with `wait`, waits for all in flight.
  void collect(bool wait);

 private:
  // The state a frame read concurrently was rendered with, kept until it reaches the writer.
  struct PendingRow {
    double t = 0.0;
    bool link_up = false, drawn = false;
    std::vector<engine::BindingState> states;
    std::optional<IntegrityCells> integrity;
    std::optional<GovernorCells> governor;
    DumpOverflow overflow = DumpOverflow::Block;
  };
  void write(std::uint64_t n, double t, bool link_up, bool drawn, const GovernorCells* governor);
  void hand_on(ReadbackFrame&& frame);
  const IntegrityCells* integrity_cells() const { return setup_.integrity ? setup_.integrity->cells() : nullptr; }

  RenderContext& ctx_;
  PngWriter& writer_;
  FramesCsv& csv_;
  FrameDumpSetup setup_;
  PixelPackReadback readback_;
  std::map<std::uint64_t, PendingRow> rows_;  // frames read back, waiting for their fence
};

}  // namespace meter::runner
