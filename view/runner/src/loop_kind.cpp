#include "meter/runner/loop_kind.hpp"

#include "meter/runner/view_error.hpp"

namespace meter::runner {

LoopKind live_loop_kind(const ViewOptions& options) {
  if (options.pipeline == "overlapped") {
    // An injected integrity fault is scheduled frame by frame against a loop that completes each
    // frame before the next is taken in; the overlapped loop does not, and running another loop
    // than the one asked for would measure something else without saying so.
    if (!options.inject_fault.empty())
      throw ViewError("--inject-fault " + options.inject_fault +
                      ": the overlapped pipeline cannot inject an integrity fault; add --pipeline concurrent (or sequential)");
    return LoopKind::Overlapped;
  }
  if (options.pipeline == "concurrent") return LoopKind::Concurrent;
  if (options.pipeline == "sequential") return LoopKind::Sequential;
  throw ViewError("--pipeline: expected overlapped, concurrent or sequential, got \"" + options.pipeline + "\"");
}

}  // namespace meter::runner
