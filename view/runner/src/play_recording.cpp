#include "meter/runner/play_recording.hpp"

#include <cmath>
#include <fstream>
#include <thread>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"
#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/runner/display_sink.hpp"
#include "meter/runner/dump_policy.hpp"
#include "meter/runner/frame_dump.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/png_writer.hpp"
#include "meter/runner/view_error.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {
namespace {

const std::vector<protocol::SignalUpdate>* updates_of(const protocol::Frame& frame) {
  if (const auto* s = std::get_if<protocol::Snapshot>(&frame.message)) return &s->signals;
  if (const auto* d = std::get_if<protocol::Delta>(&frame.message)) return &d->signals;
  return nullptr;
}

std::vector<protocol::RecordedFrame> read_recording(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw ViewError(file + ": cannot read the recording (--play)");
  std::string header;
  std::getline(in, header);
  const std::string ours = protocol::recording_header(protocol::catalog_hash());
  if (header.rfind("# ", 0) == 0 && header.find(protocol::kRecordingFormat) != std::string::npos && header != ours) {
    throw ViewError(file + ":1: recorded with another catalog (\"" + header + "\"); this view's catalog " +
                    protocol::active_catalog()->source() + " gives \"" + ours + "\" (use --catalog)");
  }
  in.seekg(0);
  return protocol::parse_recording(in, file);
}

}  // namespace

std::vector<double> play_frame_times(double fps, double span_s) {
  std::vector<double> times;
  if (!(fps > 0) || !std::isfinite(fps) || !(span_s >= 0) || !std::isfinite(span_s))
    throw ViewError("--play: fps must be > 0 and the span >= 0");
  // Exact multiples of 1/fps (no accumulated sum), so frame k's time never drifts.
  const auto count = static_cast<std::uint64_t>(std::floor(span_s * fps + 1e-9)) + 1;
  times.reserve(count);
  for (std::uint64_t k = 0; k < count; ++k) times.push_back(static_cast<double>(k) / fps);
  return times;
}

PlaySpan play_span(const std::vector<protocol::RecordedFrame>& frames, const std::string& file) {
  bool any = false;
  std::int64_t first = 0, last = 0;
  for (const auto& r : frames) {
    if (updates_of(r.frame) == nullptr) continue;
    if (!any) first = r.frame.timestamp_ns;
    last = std::max(last, r.frame.timestamp_ns);
    any = true;
  }
  if (!any) throw ViewError(file + ": the recording holds no SNAPSHOT or DELTA line (nothing to play)");
  return PlaySpan{first, static_cast<double>(last - first) / 1e9};
}

namespace {

// The recording's lines stamped at or before `now_ns` (from `next` on) applied to `table`; the
// controller's faults logged as they rise and clear, on the recording's clock.
class RecordingState {
 public:
  RecordingState(const std::vector<protocol::RecordedFrame>& frames, std::ostream& log) : frames_(frames), log_(log) {}
  const protocol::SignalTable& at(std::int64_t now_ns, double t) {
    for (; next_ < frames_.size() && frames_[next_].frame.timestamp_ns <= now_ns; ++next_) {
      const auto& frame = frames_[next_].frame;
      if (const auto* list = updates_of(frame)) {
        for (const auto& u : *list) {
          if (table_.index_of(u.id)) table_.set(u.id, protocol::SignalState{u.value, u.status, u.has_text ? u.text : std::string()});
        }
      } else if (const auto* st = std::get_if<protocol::Status>(&frame.message)) {
        note_faults(st->fault_flags, t);
      }
    }
    return table_;
  }

 private:
  void note_faults(std::uint32_t flags, double t) {
    if (const std::uint32_t raised = flags & ~faults_)
      protocol::LogLine(log_, protocol::LogLevel::Warning, "health", {protocol::log_field("fault", protocol::describe_fault_flags(raised))}) << "meter-view: t=" << t << " s: controller reports: " << protocol::describe_fault_flags(raised) << "\n";
    if (const std::uint32_t cleared = faults_ & ~flags)
      protocol::LogLine(log_, protocol::LogLevel::Info, "health", {protocol::log_field("cleared", protocol::describe_fault_flags(cleared))}) << "meter-view: t=" << t << " s: controller fault cleared: " << protocol::describe_fault_flags(cleared) << "\n";
    faults_ = flags;
  }

  const std::vector<protocol::RecordedFrame>& frames_;
  std::ostream& log_;
  protocol::SignalTable table_;
  std::size_t next_ = 0;
  std::uint32_t faults_ = 0;
};

}  // namespace

// Play mode: a policy over the engine's frame pipeline. The state comes from the recording, frame
// k at k/fps after its first update on a simulated clock (no waiting); sinks: the timing CSV and
// the PNG dump (frames.csv rows), the display last; with --hold its last frame stays shown.
void run_play(RenderContext& ctx, const ViewOptions& options, std::ostream& log) {
  const auto frames = read_recording(options.play);
  const PlaySpan span = play_span(frames, options.play);
  const auto times = play_frame_times(options.fps, options.duration_s > 0 ? options.duration_s : span.span_s);
  DumpPolicy policy = dump_policy(options);
  RecordingState state(frames, log);
  FramesCsv csv(ctx.out_dir / "frames.csv", ctx.pipeline.evaluator().bindings(), false, ctx.governed.governing(),
                ctx.display != nullptr);
  PngWriter png_writer;
  FrameDumpSetup setup;
  setup.while_full = [] { std::this_thread::sleep_for(std::chrono::milliseconds(1)); };
  FrameDump dump(ctx, png_writer, csv, std::move(setup));
  engine::FramePipeline& pipeline = ctx.pipeline;
  pipeline.set_governor(&ctx.governed);
  pipeline.add_sink(ctx.timing);
  pipeline.add_sink(dump);
  if (ctx.display_sink) {
    pipeline.add_sink(*ctx.display_sink);
    ctx.display_sink->add_listener(csv);  // frames.csv's presentation times
  }
  const double dt = 1.0 / options.fps;
  for (std::uint64_t k = 0; k < times.size(); ++k) {
    const double t = times[k];
    pipeline.evaluate(state.at(span.first_ns + std::llround(t * 1e9), t), true, k == 0 ? -1.0 : dt);
    const bool want = policy.decide(k, t, false).write;
    pipeline.render(engine::FrameRequest{k, t, false, want, want, false});
  }
  pipeline.finish();
  if (policy.dump_on_exit(times.size())) dump.dump_standing(times.size() - 1, times.back(), true);
  png_writer.finish();
  const auto& st = ctx.renderer.stats();
  log << "meter-view: played " << options.play << ": " << times.size() << " frames over " << times.back()
      << " s of recording, " << st.drawn << " drawn, " << st.skipped << " skipped (inputs unchanged), "
      << png_writer.failures() << " dumps failed\n";
  ctx.governed.summary(log);
  png_writer.check();
  if (options.hold) ctx.display_sink->hold(0, log);  // --hold needs --output (run_view)
}

}  // namespace meter::runner
