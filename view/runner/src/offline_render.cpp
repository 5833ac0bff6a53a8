#include "meter/view/offline_render.hpp"

#include "meter/platform/image.hpp"
#include "meter/view/frames_csv.hpp"
#include "meter/view/option_units.hpp"
#include "meter/view/script_log.hpp"
#include "meter/view/values_input.hpp"

namespace meter::view {

void render_offline(RenderContext& ctx, const ViewOptions& options, std::ostream& log) {
  protocol::SignalTable values;
  if (!options.values_csv.empty()) {
    load_values_csv(options.values_csv, options.at.empty() ? 1e300 : parse_time(options.at, "--at"), values);
  }
  for (const auto& s : options.sets) parse_set(s, values, "--set");
  ctx.evaluator.update(values, !options.link_lost, -1.0);  // negative dt: no smoothing, the state itself
  log_script_messages(ctx.evaluator, log);
  ctx.renderer.apply(ctx.evaluator.outputs());
  const auto ft = ctx.renderer.render(true, true);
  ctx.timing.row(0, 0.0, ft);
  const auto png = ctx.out_dir / options.png_name;
  platform::write_png(ctx.renderer.last_image(), png);
  FramesCsv csv(ctx.out_dir / "frames.csv", ctx.evaluator.bindings());
  csv.row(0, 0.0, png.filename().string(), !options.link_lost, true, ctx.evaluator.states());
  if (options.info) {
    log << "meter-view: wrote " << png.string() << " in "
        << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ctx.started).count() << " ms\n";
    log_script_stats(ctx.evaluator, log);
  }
}

}  // namespace meter::view
