// Offline mode, a policy over the engine's frame pipeline: one state (values CSV at a time, then
// --set) rendered as one forced frame straight to <out>/<png> with its frames.csv row.
#pragma once

#include <ostream>

#include "meter/runner/render_context.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

void render_offline(RenderContext& ctx, const ViewOptions& options, std::ostream& log);

}  // namespace meter::runner
