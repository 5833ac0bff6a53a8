// The clocks the inputs tell time on.
#pragma once

#include <cstdint>

namespace meter::controller {

// CLOCK_MONOTONIC in ns: replay pacing and the Modbus poll clock (immune to wall-clock steps).
std::int64_t monotonic_ns();

}  // namespace meter::controller
