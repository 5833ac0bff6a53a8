// The link's time base: steady_clock for deadlines, CLOCK_MONOTONIC nanoseconds for the sender
// timestamps in frame headers (the same clock on Linux, so a trace can relate the two).
#pragma once

#include <chrono>
#include <cstdint>

namespace meter::protocol::detail {

using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux: the sender timestamp base
std::int64_t monotonic_ns();

}  // namespace meter::protocol::detail
