// What meter-linkdump and meter-linkplay share: SIGINT/SIGTERM end the run, and CLOCK_MONOTONIC
// (the clock of the link's sender stamps) in nanoseconds.
#pragma once

#include <time.h>

#include <atomic>
#include <csignal>
#include <cstdint>

namespace meter::protocol::tool {

inline std::atomic<bool> g_stop{false};
inline void on_stop_signal(int) { g_stop = true; }
inline void stop_on_signals() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

inline std::int64_t monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

}  // namespace meter::protocol::tool
