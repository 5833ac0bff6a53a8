#include "meter/runner/stage_wait.hpp"

#include "meter/protocol/trace_events.hpp"

namespace meter::runner {

void note_wait(StageMeter& meter, TraceEvents* events, bool for_output, const char* slice, std::int64_t began_ns) {
  const std::int64_t end = protocol::monotonic_now_ns();
  for_output ? meter.waited_output(end - began_ns) : meter.waited_input(end - began_ns);
  if (events && end - began_ns > 100'000) events->complete(slice, "wait", began_ns, end, 1);
}

}  // namespace meter::runner
