#include "meter/runner/loop_kind.hpp"

#include "meter/runner/view_error.hpp"

namespace meter::runner {

LoopKind live_loop_kind(const ViewOptions& options) {
  // An injected integrity fault is scheduled against the loop it was written for: concurrent.
  if (options.pipeline == "overlapped") return options.inject_fault.empty() ? LoopKind::Overlapped : LoopKind::Concurrent;
  if (options.pipeline == "concurrent") return LoopKind::Concurrent;
  if (options.pipeline == "sequential") return LoopKind::Sequential;
  throw ViewError("--pipeline: expected overlapped, concurrent or sequential, got \"" + options.pipeline + "\"");
}

}  // namespace meter::runner
