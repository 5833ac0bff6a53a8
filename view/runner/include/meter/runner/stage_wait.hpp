// A stage's wait in meter-view's live pipeline: metered (--stats) and, past 0.1 ms, a slice on
// the render loop's line of --trace-json (docs/pipeline.md, docs/tracing.md).
#pragma once

#include <cstdint>

#include "meter/runner/stage_meter.hpp"
#include "meter/runner/trace_ring.hpp"

namespace meter::runner {

// The wait from `began_ns` (CLOCK_MONOTONIC) to now: for input, or (`for_output`) for output
// space. `events` may be nullptr.
void note_wait(StageMeter& meter, TraceEvents* events, bool for_output, const char* slice, std::int64_t began_ns);

}  // namespace meter::runner
