#include "meter/controller/input/clocks.hpp"

#include "meter/protocol/trace_events.hpp"

namespace meter::controller {

std::int64_t monotonic_ns() { return protocol::monotonic_now_ns(); }

std::int64_t realtime_ns() { return protocol::realtime_now_ns(); }

}  // namespace meter::controller
