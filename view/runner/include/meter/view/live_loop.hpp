// Live mode: subscribes to the controller's link and renders at --fps on the view's own clock
// until --duration or SIGINT/SIGTERM, dumping frames by the DumpPolicy (PNG on the writer thread,
// frames.csv row at once), with the timing CSV and the latency trace.
#pragma once

#include <ostream>

#include "meter/view/render_context.hpp"
#include "meter/view/view_options.hpp"

namespace meter::view {

// Returns once stopped; every dumped PNG is on disk then. Prints the frame counts to `log`.
void run_live(RenderContext& ctx, const ViewOptions& options, std::ostream& log);

}  // namespace meter::view
