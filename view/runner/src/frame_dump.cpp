#include "meter/runner/frame_dump.hpp"

#include <stdexcept>
#include <thread>
#include <utility>

#include "meter/protocol/trace_events.hpp"
#include "meter/runner/dump_policy.hpp"
#include "meter/runner/stage_wait.hpp"

namespace meter::runner {

FrameDump::FrameDump(RenderContext& ctx, PngWriter& writer, FramesCsv& csv, FrameDumpSetup setup)
    : ctx_(ctx), writer_(writer), csv_(csv), setup_(std::move(setup)),
      readback_(ctx.backend->gl(), ctx.renderer.width(), ctx.renderer.height(), 2, setup_.concurrent) {
  if (setup_.concurrent && !setup_.readback)
    throw std::invalid_argument("FrameDump: a concurrent dump needs the readback stage's meter (FrameDumpSetup::readback)");
}

void FrameDump::on_drawn(const engine::FrameRecord& f) {
  if (!setup_.concurrent || !f.request.output) return;
  BusyScope busy(*setup_.readback);
  if (setup_.slow_readback.count() > 0) std::this_thread::sleep_for(setup_.slow_readback);
  const std::uint64_t n = f.request.frame;
  rows_[n] = PendingRow{f.request.t, f.link_up, f.timing.drawn, *f.states, std::nullopt,
                        f.governor ? std::optional(*f.governor) : std::nullopt,
                        f.request.output_asked ? DumpOverflow::Block : setup_.overflow};
  readback_.issue(ctx_.renderer.resolved_framebuffer(), FrameInfo{n, f.request.t, f.timing.drawn, ctx_.out_dir / png_name(n)},
                  [this](ReadbackFrame&& r) { hand_on(std::move(r)); });
}

void FrameDump::on_frame(const engine::FrameRecord& f) {
  if (setup_.concurrent) {
    // The row takes the integrity monitor's cells of its frame (the monitor ran after the read).
    if (auto it = rows_.find(f.request.frame); f.request.output && it != rows_.end() && integrity_cells())
      it->second.integrity = *integrity_cells();
    collect(false);
  } else if (f.request.output) {
    if (setup_.readback) setup_.readback->item();
    write(f.request.frame, f.request.t, f.link_up, f.timing.drawn, f.governor);
  }
}

void FrameDump::finish() {
  if (setup_.concurrent) collect(true);
}

void FrameDump::dump_standing(std::uint64_t n, double t, bool link_up) {
  ctx_.renderer.read();
  const engine::FrameGovernor* governor = ctx_.pipeline.governor();
  write(n, t, link_up, false, governor ? governor->cells() : nullptr);
}

// The frame in Renderer::last_image(): its row (the state this image was rendered with) at once,
// the file from the writer.
void FrameDump::write(std::uint64_t n, double t, bool link_up, bool drawn, const GovernorCells* governor) {
  const std::string name = png_name(n);
  csv_.row(n, t, name, link_up, drawn, ctx_.pipeline.evaluator().states(), integrity_cells(), governor);
  const std::int64_t began = protocol::monotonic_now_ns();
  writer_.write(ctx_.renderer.last_image(), ctx_.out_dir / name, n, setup_.while_full);
  if (setup_.readback) note_wait(*setup_.readback, setup_.events, true, "wait for output space", began);
}

// A frame whose read finished goes into the writer's bounded buffer; with drop, a full buffer
// drops it (and it gets no row).
void FrameDump::hand_on(ReadbackFrame&& f) {
  const std::uint64_t n = f.info.frame;
  const PendingRow r = std::move(rows_.at(n));
  rows_.erase(n);
  const std::int64_t began = protocol::monotonic_now_ns();
  const std::string name = f.info.png.filename().string();
  if (writer_.offer(std::move(f), true, r.overflow, setup_.while_full)) {
    csv_.row(n, r.t, name, r.link_up, r.drawn, r.states, r.integrity ? &*r.integrity : nullptr,
             r.governor ? &*r.governor : nullptr);
  }
  // Always inside the readback stage's busy span (collect or issue): the wait is moved out of it.
  const std::int64_t end = protocol::monotonic_now_ns();
  setup_.readback->busy_was_output_wait(end - began);
  if (end - began > 100'000 && setup_.events) setup_.events->complete("wait for output space", "wait", began, end, 1);
}

void FrameDump::collect(bool wait) {
  BusyScope busy(*setup_.readback, false);
  setup_.readback->waited_input(readback_.collect(wait, [this](ReadbackFrame&& r) { hand_on(std::move(r)); }));
}

}  // namespace meter::runner
