// Live mode, a policy over the engine's frame pipeline: subscribes to the controller's link and
// renders at --fps on the view's own clock until --duration or SIGINT/SIGTERM, dumping frames by
// the DumpPolicy. Sinks: the timing CSV, the latency trace, the integrity monitor, the PNG dump
// (writer thread, frames.csv rows) and the trace-json slices.
#pragma once

#include <ostream>

#include "meter/runner/render_context.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

// Returns once stopped; every dumped PNG is on disk then. Prints the frame counts to `log`.
// Before the scene loads, when the view takes its controller's catalog: a first connection that
// lasts until the link is up (the controller's catalog, if it differed, is then taken and active)
// or options.catalog_wait_ms passed, then closes. The scene then loads against that catalog; the
// live loop connects again (same hash: no transfer). Loading a scene can take longer than the
// link timeout, so the first connection is not kept idle through it.
void fetch_controller_catalog(const ViewOptions& options, std::ostream& log);
void run_live(RenderContext& ctx, const ViewOptions& options, std::ostream& log);

}  // namespace meter::runner
