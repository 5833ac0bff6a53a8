// The clocks the inputs tell time on.
#pragma once

#include <cstdint>

namespace meter::controller {

// CLOCK_MONOTONIC in ns: replay pacing and the Modbus poll clock (immune to wall-clock steps).
std::int64_t monotonic_ns();

// Now on CLOCK_REALTIME in ns: the clock of SocketCAN's kernel receive timestamps (SO_TIMESTAMPNS),
// so live frames, the model clock and the --trace rows compare directly.
std::int64_t realtime_ns();

}  // namespace meter::controller
