#include "meter/view/live_loop.hpp"

#include <map>
#include <optional>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"
#include "meter/protocol/trace_events.hpp"

#include "meter/view/dump_policy.hpp"
#include "meter/view/frame_pacing.hpp"
#include "meter/view/frames_csv.hpp"
#include "meter/view/integrity_stage.hpp"
#include "meter/view/latency_trace.hpp"
#include "meter/view/live_stats.hpp"
#include "meter/view/pixel_pack_readback.hpp"
#include "meter/view/png_writer.hpp"
#include "meter/view/process_signals.hpp"
#include "meter/view/script_log.hpp"
#include "meter/view/trace_ring.hpp"
#include "meter/view/view_error.hpp"
#include "meter/view/view_health.hpp"

namespace meter::view {
namespace {

bool takes_controller_catalog(const ViewOptions& options) {
  return options.catalog.empty() || options.catalog_from_controller;
}

protocol::LinkOptions view_link_options(const ViewOptions& options) {
  auto lo = protocol::link_options("meter-view", std::chrono::milliseconds(options.link_timeout_ms));
  lo.take_peer_catalog = takes_controller_catalog(options);
  return lo;
}

// The frame's slices: evaluate (bindings, outputs applied), render, and inside render the
// renderer's own measured parts laid end to end from its start (update, submit, readback).
void trace_frame_events(TraceEvents& events, std::uint64_t frame, std::int64_t evaluate_began,
                        std::int64_t render_began, std::int64_t render_ended, const engine::FrameTiming& timing) {
  if (!events.on()) return;
  const std::vector<std::pair<std::string, std::int64_t>> args = {{"frame", static_cast<std::int64_t>(frame)},
                                                                  {"drawn", timing.drawn ? 1 : 0}};
  events.complete("evaluate", "view", evaluate_began, render_began, 1, args);
  events.complete("render", "view", render_began, render_ended, 1, args);
  std::int64_t t = render_began;
  const std::pair<const char*, double> parts[] = {
      {"update", timing.update_ms}, {"submit", timing.submit_ms}, {"readback", timing.gpu_readback_ms}};
  for (const auto& [name, ms] : parts) {
    const auto end = t + static_cast<std::int64_t>(ms * 1e6);
    events.complete(name, "view", t, end, 1, args);
    t = end;
  }
}

DumpOverflow dump_overflow(const ViewOptions& options, bool concurrent) {
  const std::string& p = options.dump_policy;
  if (p.empty()) return concurrent ? DumpOverflow::Drop : DumpOverflow::Block;
  if (p == "drop") return DumpOverflow::Drop;
  if (p == "block") return DumpOverflow::Block;
  throw ViewError("--dump-policy: expected drop or block, got \"" + p + "\"");
}

bool concurrent_pipeline(const ViewOptions& options) {
  if (options.pipeline == "concurrent") return true;
  if (options.pipeline == "sequential") return false;
  throw ViewError("--pipeline: expected concurrent or sequential, got \"" + options.pipeline + "\"");
}

// The state a dumped frame was rendered with, kept until the frame reaches the writer (its
// frames.csv row is written then, so a dropped frame leaves no row naming a missing PNG).
struct PendingRow {
  double t = 0.0;
  bool link_up = false, drawn = false;
  std::vector<engine::BindingState> states;
  std::optional<IntegrityCells> integrity;  // the monitor's cells for this frame, when it runs
  std::optional<GovernorCells> governor;    // the frame-rate governor's, when it is on
  DumpOverflow overflow = DumpOverflow::Block;  // requested dumps always block
};

}  // namespace

void fetch_controller_catalog(const ViewOptions& options, std::ostream& log) {
  if (!takes_controller_catalog(options)) return;
  protocol::Subscriber sub(protocol::endpoint_from_option(options.link), view_link_options(options));
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(options.catalog_wait_ms);
  while (!sub.link_up() && std::chrono::steady_clock::now() < until) sub.poll(std::chrono::milliseconds(10));
  if (!sub.link_up()) {
    log << "meter-view: no controller within " << options.catalog_wait_ms << " ms; loading the scene with the catalog "
        << sub.catalog().source() << "\n";
  }
}

void run_live(RenderContext& ctx, const ViewOptions& options, std::ostream& log) {
  using Clock = FramePacer::Clock;
  const bool concurrent = concurrent_pipeline(options);
  const DumpOverflow overflow = dump_overflow(options, concurrent);
  DumpPolicy policy = dump_policy(options);
  install_stop_handlers();
  protocol::Subscriber sub(protocol::endpoint_from_option(options.link), view_link_options(options));
  std::uint64_t catalog_seen = sub.catalog_changes();
  // A controller restarted with another catalog: its ids are the ones the table now holds.
  auto follow_catalog = [&] {
    if (sub.catalog_changes() == catalog_seen) return;
    catalog_seen = sub.catalog_changes();
    for (const auto& name : ctx.evaluator.rebind(sub.catalog())) {
      log << "meter-view: the controller's catalog " << sub.catalog().source() << " has no signal " << name
          << "; its bindings show not-available\n";
    }
  };
  IntegrityStage integrity(ctx, options, log);  // docs/integrity.md
  FramesCsv csv(ctx.out_dir / "frames.csv", ctx.evaluator.bindings(), integrity.on(), ctx.governed.governing());
  LatencyTrace trace(options.trace_csv);
  // --trace-json (docs/tracing.md): intake, evaluate, render (update, submit, readback) on the render
  // loop, encode on the PNG writer; CLOCK_MONOTONIC like the controller's file and the link's stamps.
  // --trace-on-overrun: the same slices kept for the last seconds, written when a frame overruns.
  TraceEvents events(options.trace_json, options.trace_on_overrun_ms, ctx.out_dir);
  events.thread_name(1, "render loop");
  events.thread_name(2, "png writer");
  // A link poll that applied changes is an intake slice, from the poll's start (so a poll that
  // waited for the message includes the wait); args: the newest frame's sender stamp and sequence.
  auto trace_applied = [&](std::int64_t poll_begin) {
    trace.applied(sub.last_sender_time_ns(), sub.last_sequence_applied());
    events.complete("intake", "view", poll_begin, protocol::monotonic_now_ns(), 1,
                    {{"sent_ns", sub.last_sender_time_ns()},
                     {"seq", static_cast<std::int64_t>(sub.last_sequence_applied())}});
  };
  auto poll = [&](std::chrono::milliseconds timeout) {
    const std::int64_t begin = protocol::monotonic_now_ns();
    const bool applied = sub.poll(timeout);
    if (applied) trace_applied(begin);
    return applied;
  };
  // Every pending message, not one batch: a view that renders slower than the link delivers
  // must coalesce the backlog to the latest state each frame instead of drawing it frame by
  // frame seconds late. Bounded (a flooding peer cannot hold the frame back forever); each round
  // reads up to 64 socket buffers. True when changes were applied.
  auto drain = [&] {
    bool applied = false;
    for (int round = 0; round < 16; ++round) {
      const std::int64_t begin = protocol::monotonic_now_ns();
      if (!sub.poll(std::chrono::milliseconds(0))) break;
      trace_applied(begin);
      applied = true;
    }
    return applied;
  };
  FramePacer pacer(options.fps, Clock::now());
  std::uint64_t frame = 0;
  std::int64_t encode_began = 0;  // touched on the writer thread only
  PngWriter png_writer(
      [&](std::uint64_t n) {
        trace.png_written(n);
        events.complete("encode", "view", encode_began, protocol::monotonic_now_ns(), 2,
                        {{"frame", static_cast<std::int64_t>(n)}});
      },
      [&](std::uint64_t) { encode_began = protocol::monotonic_now_ns(); });
  LiveStats stats(png_writer, options.stats ? options.stats_interval_s : 0.0, Clock::now());
  // A stage's wait, metered and (with --trace-json) a slice on the render loop's line.
  auto waited = [&](StageMeter& meter, bool for_output, const char* slice, std::int64_t began_ns) {
    const std::int64_t end = protocol::monotonic_now_ns();
    for_output ? meter.waited_output(end - began_ns) : meter.waited_input(end - began_ns);
    if (end - began_ns > 100'000) events.complete(slice, "wait", began_ns, end, 1);
  };
  // The view's faults, reported to the controller in every STATUS (and logged here once each).
  ViewHealth health;
  std::uint64_t dump_failures_seen = 0;
  auto note_dump_failures = [&](Clock::time_point now) {
    const std::uint64_t failures = png_writer.failures();
    if (failures == dump_failures_seen) return;
    if (dump_failures_seen == 0) log << "meter-view: a PNG dump failed (the view draws on): " << png_writer.first_error() << "\n";
    for (; dump_failures_seen < failures; ++dump_failures_seen) health.report(protocol::kViewFaultDumpFailed, now);
  };
  std::uint64_t drops_logged = 0;
  auto note_drops = [&] {
    const std::uint64_t drops = png_writer.dropped();
    if (drops == 0 || drops_logged > 0) return;
    drops_logged = drops;
    log << "meter-view: the PNG writer is behind: dumps are dropped (--dump-policy drop), counted at exit\n";
  };
  // The controller's faults (bus state, lost frames) from its STATUS, logged as they rise and clear.
  std::uint32_t controller_faults = 0;
  auto note_controller_faults = [&] {
    const auto st = sub.publisher_status();
    const std::uint32_t now_flags = st ? st->fault_flags : 0;
    if (now_flags == controller_faults) return;
    if (const std::uint32_t raised = now_flags & ~controller_faults)
      log << "meter-view: controller reports: " << protocol::describe_fault_flags(raised) << "\n";
    if (const std::uint32_t cleared = controller_faults & ~now_flags)
      log << "meter-view: controller fault cleared: " << protocol::describe_fault_flags(cleared) << "\n";
    controller_faults = now_flags;
  };
  auto service_link = [&] { poll(std::chrono::milliseconds(5)); };
  // Sequential: the frame was read back by render(); its row and a copy go to the writer at once.
  auto dump = [&](std::uint64_t n, double t, bool drawn) {
    const std::string name = png_name(n);
    // The row is the state this image was rendered with; the file follows from the writer.
    csv.row(n, t, name, sub.link_up(), drawn, ctx.evaluator.states(), integrity.cells(), ctx.governed.cells());
    const std::int64_t began = protocol::monotonic_now_ns();
    png_writer.write(ctx.renderer.last_image(), ctx.out_dir / name, n, service_link);
    waited(stats.readback, true, "wait for output space", began);
  };
  // Concurrent: frames read back through pixel-pack buffers (collected when their fence has
  // signalled) go into the writer's bounded buffer; with drop, a full buffer drops the frame.
  PixelPackReadback readback(ctx.backend->gl(), ctx.renderer.width(), ctx.renderer.height(), 2, concurrent);
  std::map<std::uint64_t, PendingRow> rows;  // frames read back, waiting for their fence
  auto hand_on = [&](ReadbackFrame&& f) {
    const std::uint64_t n = f.info.frame;
    const PendingRow r = std::move(rows.at(n));
    rows.erase(n);
    const std::int64_t began = protocol::monotonic_now_ns();
    const std::string name = f.info.png.filename().string();
    if (png_writer.offer(std::move(f), true, r.overflow, service_link)) {
      csv.row(n, r.t, name, r.link_up, r.drawn, r.states, r.integrity ? &*r.integrity : nullptr,
              r.governor ? &*r.governor : nullptr);
    }
    // Always inside the readback stage's busy span (collect or issue): the wait is moved out of it.
    const std::int64_t end = protocol::monotonic_now_ns();
    stats.readback.busy_was_output_wait(end - began);
    if (end - began > 100'000) events.complete("wait for output space", "wait", began, end, 1);
  };
  auto collect = [&](bool wait) {
    BusyScope busy(stats.readback, false);
    stats.readback.waited_input(readback.collect(wait, hand_on));
  };
  std::optional<Clock::time_point> changed_since;
  while (!stop_requested()) {
    if (options.duration_s > 0 && pacer.seconds_at(Clock::now()) >= options.duration_s) break;
    // Messages are consumed whenever they arrive; frames happen on the render clock only
    // (sequential), or as soon as a change may be drawn (concurrent: FramePacer::due_with_change).
    {
      BusyScope busy(stats.intake, false);
      if (drain() && !changed_since) changed_since = Clock::now();
    }
    if (concurrent) collect(false);
    const std::int64_t wait_began = protocol::monotonic_now_ns();
    if (concurrent) {
      wait_for_change_or_frame(pacer, changed_since, stop_requested, poll);
    } else {
      wait_for_frame(pacer, stop_requested, [&](std::chrono::milliseconds t) { poll(t); });
    }
    waited(stats.intake, false, "wait for input", wait_began);
    // Whatever arrived while waiting (or while the last frame rendered) is applied before the
    // frame: the frame always draws the newest state, and an EOF is seen now, not a frame later.
    {
      BusyScope busy(stats.intake);
      if (drain() && !changed_since) changed_since = Clock::now();
      follow_catalog();
    }
    const auto ft = pacer.begin_frame(Clock::now(), concurrent && changed_since.has_value());
    changed_since.reset();
    const std::int64_t t_update = LatencyTrace::now();
    const std::int64_t evaluate_began = protocol::monotonic_now_ns();
    bool want = false;
    DumpOverflow how = overflow;
    {
      BusyScope busy(stats.evaluate);
      ctx.evaluator.update(sub.signals(), sub.link_up(), ft.dt);  // read in place, no copy
      log_script_messages(ctx.evaluator, log);
      ctx.renderer.apply(ctx.evaluator.outputs());
      const DumpChoice choice = policy.decide(frame, ft.t, take_dump_request());
      want = choice.write;
      if (choice.asked) how = DumpOverflow::Block;  // --dump-at, SIGUSR1: asked for, never dropped
    }
    integrity.before_frame(frame);
    const std::int64_t render_began = protocol::monotonic_now_ns();
    const auto timing = ctx.governed.render(false, want && !concurrent);  // docs/uniform-frame-rate.md
    const std::int64_t t_rendered = LatencyTrace::now();
    const std::int64_t render_ended = protocol::monotonic_now_ns();
    // Sequential: render() read the frame back itself; its glFinish + resolve + read time counts as
    // readback. Concurrent: render()'s glFinish is render's, the pixel-pack read is metered below.
    const std::int64_t readback_ns = concurrent ? 0 : static_cast<std::int64_t>(timing.gpu_readback_ms * 1e6 * want);
    // The renderer evaluates and plans the frame, then executes it: plan and render, one call.
    const auto plan_ns = static_cast<std::int64_t>(timing.plan_ms * 1e6);
    stats.plan.busy(plan_ns);
    stats.plan.item();
    stats.render.busy(render_ended - render_began - readback_ns - plan_ns);
    stats.render.item();
    if (readback_ns > 0) stats.readback.busy(readback_ns);
    ctx.timing.row(frame, ft.t, timing, ctx.governed.cells());
    trace.frame(frame, t_update, t_rendered);
    trace_frame_events(events, frame, evaluate_began, render_began, render_ended, timing);
    ctx.governed.trace(events, frame, render_began, render_ended);
    // The frame is read back (or, concurrent, its read issued) before the integrity monitor runs:
    // the PNG is the frame as drawn and checked, not the safe-path repaint the monitor may add.
    if (concurrent && want) {
      BusyScope busy(stats.readback);
      rows[frame] = PendingRow{ft.t, sub.link_up(), timing.drawn, ctx.evaluator.states(), std::nullopt,
                               ctx.governed.cells() ? std::optional(*ctx.governed.cells()) : std::nullopt, how};
      readback.issue(ctx.renderer.resolved_framebuffer(), FrameInfo{frame, ft.t, timing.drawn, ctx.out_dir / png_name(frame)},
                     hand_on);
    }
    integrity.after_frame(frame, health, Clock::now());
    if (concurrent && want) {
      if (auto it = rows.find(frame); it != rows.end() && integrity.cells()) it->second.integrity = *integrity.cells();
    } else if (want) {
      stats.readback.item();
      dump(frame, ft.t, timing.drawn);
    }
    if (concurrent) collect(false);
    const std::int64_t frame_ns = protocol::monotonic_now_ns() - evaluate_began;
    if (const std::string file = events.frame_ended(frame, frame_ns); !file.empty()) {
      log << "meter-view: frame " << frame << " took " << frame_ns / 1'000'000 << " ms (--trace-on-overrun "
          << options.trace_on_overrun_ms << "): the last seconds of trace in " << file << "\n";
    }
    ++frame;
    const auto ended = Clock::now();
    if (pacer.end_frame(ended)) health.report(protocol::kViewFaultFrameDeadline, ended);
    note_dump_failures(ended);
    note_drops();
    note_controller_faults();
    sub.send_status(ctx.renderer.stats().drawn, health.flags(ended));
    stats.print_if_due(ended, log);
    ctx.governed.print_if_due(ended, log);
  }
  if (concurrent) collect(true);
  if (policy.dump_on_exit(frame)) {
    ctx.renderer.read();
    dump(frame - 1, pacer.seconds_at(Clock::now()), false);
  }
  png_writer.finish();  // every dumped frame is on disk before the exit status says so
  if (!events.close()) log << "meter-view: write error on " << options.trace_json << "\n";
  const auto& st = ctx.renderer.stats();
  log << "meter-view: " << st.frames << " frames, " << st.drawn << " drawn, " << st.skipped
      << " skipped (inputs unchanged), " << health.count(protocol::kViewFaultFrameDeadline)
      << " frame deadlines missed, " << png_writer.failures() << " dumps failed, " << png_writer.dropped()
      << " dumps dropped (writer busy)\n";
  if (options.stats) {
    const auto end = Clock::now();
    log << "meter-view: " << options.pipeline << " pipeline, readback "
        << (readback.asynchronous() ? "through pixel-pack buffers" : "synchronous") << ", dump policy "
        << (overflow == DumpOverflow::Drop ? "drop" : "block") << "\n";
    LiveStats::print(stats.totals(end), pacer.seconds_at(end), log);
  }
  ctx.governed.summary(log);
  integrity.summary(log);
  log_script_stats(ctx.evaluator, log);
  png_writer.check();  // a failed dump makes the exit status say so
}

}  // namespace meter::view
