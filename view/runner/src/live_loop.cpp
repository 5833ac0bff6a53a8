#include "meter/view/live_loop.hpp"

#include <cstdio>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"
#include "meter/protocol/trace_events.hpp"

#include "meter/view/dump_policy.hpp"
#include "meter/view/frame_pacing.hpp"
#include "meter/view/frames_csv.hpp"
#include "meter/view/integrity_stage.hpp"
#include "meter/view/latency_trace.hpp"
#include "meter/view/option_units.hpp"
#include "meter/view/png_writer.hpp"
#include "meter/view/process_signals.hpp"
#include "meter/view/view_health.hpp"

namespace meter::view {
namespace {

DumpPolicy dump_policy(const ViewOptions& options) {
  std::vector<double> at;
  for (const auto& text : options.dump_at) at.push_back(parse_time(text, "--dump-at"));
  return DumpPolicy(options.dump_every, std::move(at), options.dump_last);
}

std::string png_name(std::uint64_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(frame));
  return name;
}

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
void trace_frame_events(protocol::TraceEventFile& events, std::uint64_t frame, std::int64_t evaluate_began,
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
  FramesCsv csv(ctx.out_dir / "frames.csv", ctx.evaluator.bindings(), integrity.on());
  LatencyTrace trace(options.trace_csv);
  // --trace-json (docs/tracing.md): intake, evaluate, render (update, submit, readback) on the render
  // loop, encode on the PNG writer; CLOCK_MONOTONIC like the controller's file and the link's stamps.
  protocol::TraceEventFile events(options.trace_json, "meter-view");
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
    if (sub.poll(timeout)) trace_applied(begin);
  };
  // Every pending message, not one batch: a view that renders slower than the link delivers
  // must coalesce the backlog to the latest state each frame instead of drawing it frame by
  // frame seconds late. Bounded (a flooding peer cannot hold the frame back forever); each round
  // reads up to 64 socket buffers.
  auto drain = [&] {
    for (int round = 0; round < 16; ++round) {
      const std::int64_t begin = protocol::monotonic_now_ns();
      if (!sub.poll(std::chrono::milliseconds(0))) break;
      trace_applied(begin);
    }
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
  // The view's faults, reported to the controller in every STATUS (and logged here once each).
  ViewHealth health;
  std::uint64_t dump_failures_seen = 0;
  auto note_dump_failures = [&](Clock::time_point now) {
    const std::uint64_t failures = png_writer.failures();
    if (failures == dump_failures_seen) return;
    if (dump_failures_seen == 0) log << "meter-view: a PNG dump failed (the view draws on): " << png_writer.first_error() << "\n";
    for (; dump_failures_seen < failures; ++dump_failures_seen) health.report(protocol::kViewFaultDumpFailed, now);
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
  auto dump = [&](std::uint64_t n, double t, bool drawn) {
    const std::string name = png_name(n);
    // The row is the state this image was rendered with; the file follows from the writer.
    csv.row(n, t, name, sub.link_up(), drawn, ctx.evaluator.states(), integrity.cells());
    png_writer.write(ctx.renderer.last_image(), ctx.out_dir / name, n, [&] { poll(std::chrono::milliseconds(5)); });
  };
  while (!stop_requested()) {
    if (options.duration_s > 0 && pacer.seconds_at(Clock::now()) >= options.duration_s) break;
    // Messages are consumed whenever they arrive; frames happen on the render clock only.
    drain();
    wait_for_frame(pacer, stop_requested, poll);
    // Whatever arrived while waiting (or while the last frame rendered) is applied before the
    // frame: the frame always draws the newest state, and an EOF is seen now, not a frame later.
    drain();
    follow_catalog();
    const auto ft = pacer.begin_frame(Clock::now());
    const std::int64_t t_update = LatencyTrace::now();
    const std::int64_t evaluate_began = protocol::monotonic_now_ns();
    ctx.evaluator.update(sub.signals(), sub.link_up(), ft.dt);  // read in place, no copy
    ctx.renderer.apply(ctx.evaluator.outputs());
    const bool want = policy.decide(frame, ft.t, take_dump_request());
    const std::int64_t render_began = protocol::monotonic_now_ns();
    integrity.before_frame(frame);
    const auto timing = ctx.renderer.render(false, want);
    integrity.after_frame(frame, health, Clock::now());
    const std::int64_t t_rendered = LatencyTrace::now();
    ctx.timing.row(frame, ft.t, timing);
    trace.frame(frame, t_update, t_rendered);
    trace_frame_events(events, frame, evaluate_began, render_began, protocol::monotonic_now_ns(), timing);
    if (want) dump(frame, ft.t, timing.drawn);
    ++frame;
    const auto ended = Clock::now();
    if (pacer.end_frame(ended)) health.report(protocol::kViewFaultFrameDeadline, ended);
    note_dump_failures(ended);
    note_controller_faults();
    sub.send_status(ctx.renderer.stats().drawn, health.flags(ended));
  }
  if (policy.dump_on_exit(frame)) {
    ctx.renderer.read();
    dump(frame - 1, pacer.seconds_at(Clock::now()), false);
  }
  png_writer.finish();  // every dumped frame is on disk before the exit status says so
  if (!events.close()) log << "meter-view: write error on " << options.trace_json << "\n";
  const auto& st = ctx.renderer.stats();
  log << "meter-view: " << st.frames << " frames, " << st.drawn << " drawn, " << st.skipped
      << " skipped (inputs unchanged), " << health.count(protocol::kViewFaultFrameDeadline)
      << " frame deadlines missed, " << png_writer.failures() << " dumps failed\n";
  integrity.summary(log);
  png_writer.check();  // a failed dump makes the exit status say so
}

}  // namespace meter::view
