#include "meter/runner/offline_render.hpp"

#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/platform/image.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/display_sink.hpp"
#include "meter/runner/option_units.hpp"
#include "meter/runner/script_log.hpp"
#include "meter/runner/values_input.hpp"

namespace meter::runner {

// Offline mode: a policy over the engine's frame pipeline with one frame, forced and read back: the
// state from --values / --set; its sink the timing CSV; the PNG and its frames.csv row written here.
void render_offline(RenderContext& ctx, const ViewOptions& options, std::ostream& log) {
  protocol::SignalTable values;
  if (!options.values_csv.empty()) {
    load_values_csv(options.values_csv, options.at.empty() ? 1e300 : parse_time(options.at, "--at"), values);
  }
  for (const auto& s : options.sets) parse_set(s, values, "--set");
  engine::FramePipeline& pipeline = ctx.pipeline;
  FramesCsv csv(ctx.out_dir / "frames.csv", ctx.pipeline.evaluator().bindings(), false, false, ctx.display != nullptr);
  pipeline.add_sink(ctx.timing);
  if (ctx.display_sink) {
    pipeline.add_sink(*ctx.display_sink);
    ctx.display_sink->add_listener(csv);
  }
  pipeline.evaluate(values, !options.link_lost, -1.0);  // negative dt: no smoothing, the state itself
  log_script_messages(ctx.pipeline.evaluator(), log);
  pipeline.render(engine::FrameRequest{0, 0.0, true, true, false, false});  // read back; written below, not by a sink
  pipeline.finish();
  const auto png = ctx.out_dir / options.png_name;
  platform::write_png(ctx.renderer.last_image(), png);
  csv.row(0, 0.0, png.filename().string(), !options.link_lost, true, ctx.pipeline.evaluator().states());
  if (options.info) {
    log << "meter-view: wrote " << png.string() << " in "
        << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ctx.started).count() << " ms\n";
    log_script_stats(ctx.pipeline.evaluator(), log);
  }
  // The one frame stays on the display until --duration seconds passed (0: until SIGINT/SIGTERM).
  if (ctx.display_sink) ctx.display_sink->hold(options.duration_s, log);
}

}  // namespace meter::runner
