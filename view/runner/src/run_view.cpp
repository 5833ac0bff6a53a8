#include "meter/runner/run_view.hpp"

#include "meter/platform/display.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/runner/live_loop.hpp"
#include "meter/runner/loop_kind.hpp"
#include "meter/runner/offline_render.hpp"
#include "meter/runner/play_recording.hpp"
#include "meter/runner/process_signals.hpp"
#include "meter/runner/render_context.hpp"
#include "meter/runner/view_error.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {

int run_view(const ViewOptions& options, std::ostream& log) {
  install_dump_request_handler();
  try {
    if (options.hold && (options.play.empty() || options.output == "offscreen"))
      throw ViewError("--hold keeps a played recording's last frame on a display: it needs --play and --output");
    protocol::use_catalog_option(options.catalog);  // before the scene: its bindings name catalog signals
    if (!options.play.empty()) {
      RenderContext ctx(options, log);
      run_play(ctx, options, log);
    } else if (options.link.empty()) {
      RenderContext ctx(options, log);
      render_offline(ctx, options, log);
    } else {
      live_loop_kind(options);  // a --pipeline it cannot run refused before the controller is waited for
      fetch_controller_catalog(options, log);
      RenderContext ctx(options, log);
      run_live(ctx, options, log);
    }
    return 0;
  } catch (const platform::DisplayLost& e) {
    protocol::LogLine(log, protocol::LogLevel::Error, "display") << "meter-view: error: the display went away: " << e.what() << "\n";
    return kExitDisplayLost;
  } catch (const std::exception& e) {
    protocol::LogLine(log, protocol::LogLevel::Error, "view") << "meter-view: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::runner
