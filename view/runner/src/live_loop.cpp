// Live mode: a policy over the engine's frame pipeline. The state comes from the controller's link
// (every pending message applied right before a frame); a frame is due on the view's clock
// (sequential) or as soon as a change may be drawn (concurrent, overlapped). Overlapped: a frame's
// GL work executes, fenced, while the next frame is taken in, evaluated and planned. Its sinks, in
// order: the timing CSV, the latency trace, the integrity monitor, the display (with --output: the
// monitor checks the frame in its back buffer), the PNG dump (frames.csv rows), the trace-json slices.
#include "meter/runner/live_loop.hpp"

#include <algorithm>
#include <optional>
#include <thread>

#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/link_stats_text.hpp"
#include "meter/protocol/trace_events.hpp"
#include "meter/protocol/wire.hpp"
#include "meter/runner/display_latch.hpp"
#include "meter/runner/display_sink.hpp"
#include "meter/runner/dump_policy.hpp"
#include "meter/runner/frame_dump.hpp"
#include "meter/runner/frame_pacing.hpp"
#include "meter/runner/frame_trace.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/integrity_stage.hpp"
#include "meter/runner/latency_trace.hpp"
#include "meter/runner/live_stats.hpp"
#include "meter/runner/loop_kind.hpp"
#include "meter/runner/png_writer.hpp"
#include "meter/runner/process_signals.hpp"
#include "meter/runner/script_log.hpp"
#include "meter/runner/service_notify.hpp"
#include "meter/runner/slow_stage.hpp"
#include "meter/runner/stage_wait.hpp"
#include "meter/runner/trace_ring.hpp"
#include "meter/runner/view_error.hpp"
#include "meter/runner/view_health.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {
namespace {

using Clock = FramePacer::Clock;

bool takes_controller_catalog(const ViewOptions& options) {
  return options.catalog.empty() || options.catalog_from_controller;
}

protocol::LinkOptions view_link_options(const ViewOptions& options) {
  auto lo = protocol::link_options("meter-view", std::chrono::milliseconds(options.link_timeout_ms));
  lo.take_peer_catalog = takes_controller_catalog(options);
  lo.key_file = options.key_file;
  lo.insecure_link = options.insecure_link;
  return lo;
}

DumpOverflow dump_overflow(const ViewOptions& options, bool concurrent) {
  const std::string& p = options.dump_policy;
  if (p.empty()) return concurrent ? DumpOverflow::Drop : DumpOverflow::Block;
  if (p == "drop") return DumpOverflow::Drop;
  if (p == "block") return DumpOverflow::Block;
  throw ViewError("--dump-policy: expected drop or block, got \"" + p + "\"");
}

// The link's endpoint, once SIGINT/SIGTERM end the loop (installed before the link connects).
protocol::Endpoint live_endpoint(const ViewOptions& options) {
  install_stop_handlers();
  return protocol::endpoint_from_option(options.link);
}

class LiveLoop {
 public:
  LiveLoop(RenderContext& ctx, const ViewOptions& options, std::ostream& log);
  void run();

 private:
  bool poll(std::chrono::milliseconds timeout);
  bool drain();
  void trace_applied(std::int64_t poll_begin);
  void follow_catalog();
  FramePacer::FrameTime intake();
  void wait_for_display();
  engine::FrameRequest evaluate(const FramePacer::FrameTime& ft);
  void frame(const FramePacer::FrameTime& ft);
  void frame_overlapped(const FramePacer::FrameTime& ft);
  void complete(StageMeter* waiter, bool for_output);
  void meter_frame(const engine::FrameRecord& r);
  void after_frame();
  void note_dump_failures(Clock::time_point now);
  void note_drops();
  void note_controller_faults();
  void summary();

  RenderContext& ctx_;
  const ViewOptions& options_;
  std::ostream& log_;
  const bool concurrent_, overlapped_;
  const SlowStage slow_;  // test only (--inject-slow-stage)
  // Overlapped: the frame in flight completes before the next is evaluated when the governor
  // runs (it pairs a frame's time with the renderer's load of it).
  bool completes_first_ = false;
  const DumpOverflow overflow_;
  DumpPolicy policy_;
  protocol::Subscriber sub_;
  std::uint64_t catalog_seen_;
  ViewHealth health_;  // the view's faults, reported to the controller in every STATUS
  IntegrityStage integrity_;  // docs/integrity.md
  FramesCsv csv_;
  LatencyTrace trace_;
  // --trace-json (docs/tracing.md): intake, evaluate, render (update, submit, readback) on the
  // render loop, encode on the PNG writer; CLOCK_MONOTONIC like the controller's file and the
  // link's stamps. --trace-on-overrun: the same slices kept for the last seconds.
  TraceEvents events_;
  FramePacer pacer_;
  std::int64_t encode_began_ = 0;  // touched on the writer thread only
  PngWriter png_writer_;
  LiveStats stats_;
  FrameDump dump_;
  FrameTrace frame_trace_;
  std::optional<DisplayLatch> latch_;  // with a display: when a due frame is drawn (--latch)
  std::uint64_t frame_ = 0;
  std::optional<Clock::time_point> changed_since_;
  std::uint64_t dump_failures_seen_ = 0, drops_logged_ = 0;
  std::uint32_t controller_faults_ = 0;  // from the controller's STATUS, logged as they rise and clear
};

LiveLoop::LiveLoop(RenderContext& ctx, const ViewOptions& options, std::ostream& log)
    : ctx_(ctx),
      options_(options),
      log_(log),
      concurrent_(live_loop_kind(options) != LoopKind::Sequential),
      overlapped_(live_loop_kind(options) == LoopKind::Overlapped),
      slow_(parse_slow_stage(options.inject_slow_stage, overlapped_)),
      overflow_(dump_overflow(options, concurrent_)),
      policy_(dump_policy(options)),
      sub_(live_endpoint(options), view_link_options(options)),
      catalog_seen_(sub_.catalog_changes()),
      integrity_(ctx, options, health_, log),
      csv_(ctx.out_dir / "frames.csv", ctx.pipeline.evaluator().bindings(), integrity_.on(), ctx.governed.governing(),
           ctx.display != nullptr),
      trace_(options.trace_csv),
      events_(options.trace_json, options.trace_on_overrun_ms, ctx.out_dir),
      pacer_(options.fps, Clock::now()),
      png_writer_(
          [this](std::uint64_t n) {
            trace_.png_written(n);
            events_.complete("encode", "view", encode_began_, protocol::monotonic_now_ns(), 2,
                             {{"frame", static_cast<std::int64_t>(n)}});
          },
          [this](std::uint64_t) {
            encode_began_ = protocol::monotonic_now_ns();
            slow_.in("encode");  // inside the encode stage's busy span
          }),
      stats_(png_writer_, options.stats ? options.stats_interval_s : 0.0, Clock::now()),
      dump_(ctx, png_writer_, csv_,
            FrameDumpSetup{concurrent_, overflow_, &integrity_, &stats_.readback, &events_,
                           [this] { poll(std::chrono::milliseconds(5)); }, slow_.of("readback")}),
      frame_trace_(events_, options.trace_on_overrun_ms, log) {
  events_.thread_name(1, "render loop");
  events_.thread_name(2, "png writer");
  events_.thread_name(3, "gpu");
  png_writer_.slow_check(slow_.of("check"));
  if (!slow_.stage.empty()) protocol::LogLine(log_, protocol::LogLevel::Warning, "pipeline") << "meter-view: TEST SLOW STAGE: " << options.inject_slow_stage << "\n";
  if (overlapped_) {
    ctx_.pipeline.set_overlap(true);
    completes_first_ = ctx.governed.governing() || !options.inject_cost.empty();
  }
  ctx_.pipeline.set_governor(&ctx.governed);  // docs/uniform-frame-rate.md
  // With a display, it comes before the dump: the monitor judges the frame in the display's back
  // buffer (the display's sink asks it) and the dump's rows take the cells of their own frame.
  for (engine::FrameSink* sink : std::initializer_list<engine::FrameSink*>{&ctx.timing, &trace_, &integrity_})
    ctx_.pipeline.add_sink(*sink);
  if (ctx.display_sink) {  // its feedback to the traces and frames.csv
    ctx_.pipeline.add_sink(*ctx.display_sink);
    if (integrity_.on()) ctx.display_sink->check_with(integrity_);
    ctx.display_sink->report_to(health_);
    latch_.emplace(*ctx.display, parse_latch_pacing(options.latch));
    for (PresentationListener* l : std::initializer_list<PresentationListener*>{&trace_, &frame_trace_, &csv_, &*latch_})
      ctx.display_sink->add_listener(*l);
    protocol::LogLine(log_, protocol::LogLevel::Info, "display") << "meter-view: display pacing: --latch " << options.latch << "\n";
  }
  ctx_.pipeline.add_sink(dump_);
  ctx_.pipeline.add_sink(frame_trace_);
}

// A link poll that applied changes is an intake slice, from the poll's start (so a poll that
// waited for the message includes the wait); args: the newest frame's sender stamp and sequence.
void LiveLoop::trace_applied(std::int64_t poll_begin) {
  trace_.applied(sub_.last_sender_time_ns(), sub_.last_sequence_applied());
  events_.complete("intake", "view", poll_begin, protocol::monotonic_now_ns(), 1,
                   {{"sent_ns", sub_.last_sender_time_ns()},
                    {"seq", static_cast<std::int64_t>(sub_.last_sequence_applied())}});
}

bool LiveLoop::poll(std::chrono::milliseconds timeout) {
  const std::int64_t begin = protocol::monotonic_now_ns();
  const bool applied = sub_.poll(timeout);
  if (applied) trace_applied(begin);
  return applied;
}

// Every pending message, not one batch: a view that renders slower than the link delivers must
// coalesce the backlog to the latest state each frame instead of drawing it frame by frame seconds
// late. Bounded (a flooding peer cannot hold the frame back forever); each round reads up to 64
// socket buffers. True when changes were applied.
bool LiveLoop::drain() {
  bool applied = false;
  for (int round = 0; round < 16; ++round) {
    const std::int64_t begin = protocol::monotonic_now_ns();
    if (!sub_.poll(std::chrono::milliseconds(0))) break;
    trace_applied(begin);
    applied = true;
  }
  return applied;
}

// A controller restarted with another catalog: its ids are the ones the table now holds.
void LiveLoop::follow_catalog() {
  if (sub_.catalog_changes() == catalog_seen_) return;
  catalog_seen_ = sub_.catalog_changes();
  for (const auto& name : ctx_.pipeline.evaluator().rebind(sub_.catalog())) {
    protocol::LogLine(log_, protocol::LogLevel::Warning, "link", {protocol::log_field("signal", name)}) << "meter-view: the controller's catalog " << sub_.catalog().source() << " has no signal " << name
         << "; its bindings show not-available\n";
  }
}

// Messages are consumed whenever they arrive; frames happen on the render clock only
// (sequential), or as soon as a change may be drawn (concurrent: FramePacer::due_with_change).
// Whatever arrived while waiting (or while the last frame rendered) is applied before the frame:
// the frame always draws the newest state, and an EOF is seen now, not a frame later.
FramePacer::FrameTime LiveLoop::intake() {
  {
    BusyScope busy(stats_.intake, false);
    if (drain() && !changed_since_) changed_since_ = Clock::now();
  }
  if (overlapped_) ctx_.pipeline.poll_in_flight();  // before the dump's collect: the frame's "drawn" stamp
  if (concurrent_) dump_.collect(false);
  const std::int64_t wait_began = protocol::monotonic_now_ns();
  // Idle with a frame in flight: its fence is waited for 1 ms at a time between link polls, so it
  // is stamped drawn as it finishes and handed on; it is not waited for longer: were the GPU still
  // busy when the next frame falls due, that frame's intake, evaluation and plan would not overlap it.
  auto wait_poll = [this](std::chrono::milliseconds t) {
    if (!ctx_.pipeline.in_flight()) return poll(t);
    if (!ctx_.pipeline.poll_in_flight(std::min<std::chrono::nanoseconds>(t, std::chrono::milliseconds(1))))
      return poll(std::chrono::milliseconds(0));
    complete(nullptr, false);
    return false;
  };
  if (concurrent_) {
    wait_for_change_or_frame(pacer_, changed_since_, stop_requested, wait_poll);
  } else {
    wait_for_frame(pacer_, stop_requested, [&](std::chrono::milliseconds t) { wait_poll(t); });
  }
  note_wait(stats_.intake, &events_, false, "wait for input", wait_began);
  wait_for_display();
  {
    BusyScope busy(stats_.intake);
    slow_.in("intake");
    if (drain() && !changed_since_) changed_since_ = Clock::now();
    follow_catalog();
  }
  if (overlapped_) ctx_.pipeline.poll_in_flight();
  const auto ft = pacer_.begin_frame(Clock::now(), concurrent_ && changed_since_.has_value());
  changed_since_.reset();
  return ft;
}

// With a display, a due frame is drawn once the screen took the frame before (its frame callback
// came): one frame in flight, drawn from the newest state and shown as soon as it is drawn, rather
// than drawn early and held in the copy until the callback (a period older by then). With late
// latching (--latch late) it waits on until the last safe moment before the display's next latch
// (DisplayLatch). The link is drained meanwhile in 1 ms slices (the last millisecond slept), and a
// frame still on the GPU is completed (shown) first.
void LiveLoop::wait_for_display() {
  if (!ctx_.display) return;
  std::int64_t began = protocol::monotonic_now_ns();
  bool took = false;  // the display took the frame before
  while (!stop_requested()) {
    if (ctx_.pipeline.in_flight()) {
      if (ctx_.pipeline.poll_in_flight(std::chrono::milliseconds(1))) complete(nullptr, false);
    } else if (!took) {
      if ((took = ctx_.display->ready_for_frame(1))) {
        note_wait(stats_.intake, &events_, false, "wait for the display", began);
        began = protocol::monotonic_now_ns();
        continue;
      }
    } else {
      const std::int64_t left = latch_ ? latch_->wait_left_ns(protocol::monotonic_now_ns()) : 0;
      if (left <= 0) break;
      if (left < 1'000'000) {
        std::this_thread::sleep_for(std::chrono::nanoseconds(left));
        continue;
      }
      if (poll(std::chrono::milliseconds(1)) && !changed_since_) changed_since_ = Clock::now();
      continue;
    }
    if (drain() && !changed_since_) changed_since_ = Clock::now();
  }
  if (took) note_wait(stats_.intake, &events_, false, "wait for the latch", began);
  if (latch_) latch_->starting(protocol::monotonic_now_ns());
}

// The link's state through the bindings, and what the frame is asked for. Sequential: the render
// reads a dumped frame back itself; otherwise the dump reads it through pixel-pack buffers.
engine::FrameRequest LiveLoop::evaluate(const FramePacer::FrameTime& ft) {
  engine::FrameRequest request{frame_, ft.t};
  BusyScope busy(stats_.evaluate);
  slow_.in("evaluate");
  ctx_.pipeline.evaluate(sub_.signals(), sub_.link_up(), ft.dt);  // read in place, no copy
  log_script_messages(ctx_.pipeline.evaluator(), log_);
  const DumpChoice choice = policy_.decide(frame_, ft.t, take_dump_request());
  request.output = choice.write;
  request.output_asked = choice.asked;  // --dump-at, SIGUSR1: asked for, never dropped
  request.read = choice.write && !concurrent_;
  return request;
}

void LiveLoop::frame(const FramePacer::FrameTime& ft) {
  if (overlapped_) {
    frame_overlapped(ft);
  } else {
    meter_frame(ctx_.pipeline.render(evaluate(ft)));
    ++frame_;
  }
  if (!latch_ || !latch_->late()) return;
  // Late latching: the frame was started for the next latch, so it is completed and shown at
  // once (not overlapped with the next frame's intake), and its render time learnt.
  if (ctx_.pipeline.in_flight()) complete(&stats_.render, true);
  latch_->drawn(frame_ - 1, ctx_.display_sink->last_presented_frame() == frame_ - 1, protocol::monotonic_now_ns());
}

// CUBE's double buffer between the CPU stages and the GPU: frame N executes while N+1 is taken in
// (intake), evaluated and planned; then N is completed (its fence waited for: render's wait for
// output space; its sinks run) and N+1 submitted, fenced, in its place.
void LiveLoop::frame_overlapped(const FramePacer::FrameTime& ft) {
  if (completes_first_) complete(&stats_.evaluate, false);
  const engine::FrameRequest request = evaluate(ft);
  ctx_.pipeline.poll_in_flight();
  {
    BusyScope busy(stats_.plan);
    slow_.in("plan");
    ctx_.pipeline.plan(request);
  }
  ctx_.pipeline.poll_in_flight();
  complete(&stats_.render, true);
  {
    BusyScope busy(stats_.render);
    slow_.in("render");
    ctx_.pipeline.draw();
  }
  ctx_.pipeline.poll_in_flight();
  ++frame_;
}

// The frame in flight waited for and handed to the sinks. The wait is `waiter`'s: for output
// space (render: the GPU still holds the frame before) or for input (evaluate: the governor
// learns from that frame first); nullptr: the loop was about to wait for input anyway.
void LiveLoop::complete(StageMeter* waiter, bool for_output) {
  const engine::FrameRecord* r = ctx_.pipeline.complete();
  if (!r) return;
  if (waiter && for_output) waiter->waited_output(r->gpu_wait_ns);
  if (waiter && !for_output) waiter->waited_input(r->gpu_wait_ns);
  stats_.gpu.busy(r->gpu_busy_until_ns - r->submitted_ns);
  stats_.gpu.item();
}

// Sequential and concurrent: the renderer evaluates and plans the frame, then executes it: plan
// and render, one call.
// Sequential: render() read the frame back itself; its glFinish + resolve + read time counts as
// readback. Concurrent: render()'s glFinish is render's, the pixel-pack read is metered by the dump.
void LiveLoop::meter_frame(const engine::FrameRecord& r) {
  const engine::FrameTiming& timing = r.timing;
  const std::int64_t readback_ns =
      concurrent_ ? 0 : static_cast<std::int64_t>(timing.gpu_readback_ms * 1e6 * r.request.output);
  const auto plan_ns = static_cast<std::int64_t>(timing.plan_ms * 1e6);
  stats_.plan.busy(plan_ns);
  stats_.plan.item();
  stats_.render.busy(r.render_ended_ns - r.render_began_ns - readback_ns - plan_ns);
  stats_.render.item();
  if (readback_ns > 0) stats_.readback.busy(readback_ns);
}

void LiveLoop::note_dump_failures(Clock::time_point now) {
  const std::uint64_t failures = png_writer_.failures();
  if (failures == dump_failures_seen_) return;
  if (dump_failures_seen_ == 0)
    protocol::LogLine(log_, protocol::LogLevel::Error, "dump") << "meter-view: a PNG dump failed (the view draws on): " << png_writer_.first_error() << "\n";
  for (; dump_failures_seen_ < failures; ++dump_failures_seen_) health_.report(protocol::kViewFaultDumpFailed, now);
}

void LiveLoop::note_drops() {
  const std::uint64_t drops = png_writer_.dropped();
  if (drops == 0 || drops_logged_ > 0) return;
  drops_logged_ = drops;
  protocol::LogLine(log_, protocol::LogLevel::Warning, "dump") << "meter-view: the PNG writer is behind: dumps are dropped (--dump-policy drop), counted at exit\n";
}

void LiveLoop::note_controller_faults() {
  const auto st = sub_.publisher_status();
  const std::uint32_t now_flags = st ? st->fault_flags : 0;
  if (now_flags == controller_faults_) return;
  if (const std::uint32_t raised = now_flags & ~controller_faults_)
    protocol::LogLine(log_, protocol::LogLevel::Warning, "health", {protocol::log_field("fault", protocol::describe_fault_flags(raised))}) << "meter-view: controller reports: " << protocol::describe_fault_flags(raised) << "\n";
  if (const std::uint32_t cleared = controller_faults_ & ~now_flags)
    protocol::LogLine(log_, protocol::LogLevel::Info, "health", {protocol::log_field("cleared", protocol::describe_fault_flags(cleared))}) << "meter-view: controller fault cleared: " << protocol::describe_fault_flags(cleared) << "\n";
  controller_faults_ = now_flags;
}

// The frame's deadline, the faults noted, STATUS sent to the controller, --stats lines.
void LiveLoop::after_frame() {
  const auto ended = Clock::now();
  if (pacer_.end_frame(ended)) health_.report(protocol::kViewFaultFrameDeadline, ended);
  note_dump_failures(ended);
  note_drops();
  note_controller_faults();
  sub_.send_status(ctx_.renderer.stats().drawn, health_.flags(ended));
  stats_.print_if_due(ended, log_);
  ctx_.governed.print_if_due(ended, log_);
}

void LiveLoop::run() {
  ViewService service(log_);  // the service manager: ready, keep-alives, stopping (docs/deploy.md)
  while (!stop_requested()) {
    if (options_.duration_s > 0 && pacer_.seconds_at(Clock::now()) >= options_.duration_s) break;
    frame(intake());
    after_frame();
    service.frame_drawn();
  }
  service.stopping();
  ctx_.pipeline.finish();
  if (policy_.dump_on_exit(frame_)) dump_.dump_standing(frame_ - 1, pacer_.seconds_at(Clock::now()), sub_.link_up());
  png_writer_.finish();  // every dumped frame is on disk before the exit status says so
  if (!events_.close()) protocol::LogLine(log_, protocol::LogLevel::Error, "trace", {protocol::log_field("file", options_.trace_json)}) << "meter-view: write error on " << options_.trace_json << "\n";
  summary();
  png_writer_.check();  // a failed dump makes the exit status say so
}

void LiveLoop::summary() {
  const auto& st = ctx_.renderer.stats();
  log_ << "meter-view: " << st.frames << " frames, " << st.drawn << " drawn, " << st.skipped
       << " skipped (inputs unchanged), " << health_.count(protocol::kViewFaultFrameDeadline)
       << " frame deadlines missed, " << png_writer_.failures() << " dumps failed, " << png_writer_.dropped()
       << " dumps dropped (writer busy)\n";
  log_ << "meter-view: link: " << protocol::link_stats_text(sub_.stats()) << "\n";
  if (options_.stats) {
    const auto end = Clock::now();
    log_ << "meter-view: " << options_.pipeline << " pipeline, readback "
         << (dump_.asynchronous() ? "through pixel-pack buffers" : "synchronous") << ", dump policy "
         << (overflow_ == DumpOverflow::Drop ? "drop" : "block") << "\n";
    LiveStats::print(stats_.totals(end), pacer_.seconds_at(end), log_);
  }
  ctx_.governed.summary(log_);
  if (latch_) latch_->summary(log_);
  integrity_.summary(log_);
  log_script_stats(ctx_.pipeline.evaluator(), log_);
}

}  // namespace

void fetch_controller_catalog(const ViewOptions& options, std::ostream& log) {
  if (!takes_controller_catalog(options)) return;
  protocol::Subscriber sub(protocol::endpoint_from_option(options.link), view_link_options(options));
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(options.catalog_wait_ms);
  while (!sub.link_up() && std::chrono::steady_clock::now() < until) sub.poll(std::chrono::milliseconds(10));
  if (!sub.link_up()) {
    protocol::LogLine(log, protocol::LogLevel::Warning, "link") << "meter-view: no controller within " << options.catalog_wait_ms << " ms; loading the scene with the catalog "
        << sub.catalog().source() << "\n";
  }
}

void run_live(RenderContext& ctx, const ViewOptions& options, std::ostream& log) {
  LiveLoop loop(ctx, options, log);
  loop.run();
}

}  // namespace meter::runner
