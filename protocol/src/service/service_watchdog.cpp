#include "meter/protocol/service_watchdog.hpp"

#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <cstring>

#include "meter/protocol/trace_events.hpp"

namespace meter::protocol {
namespace {

// A whole decimal count, nothing before or after it.
std::optional<std::uint64_t> parse_count(const char* text) {
  std::uint64_t v = 0;
  const char* end = text + std::strlen(text);
  auto [p, ec] = std::from_chars(text, end, v);
  if (ec != std::errc() || p != end || p == text) return std::nullopt;
  return v;
}

}  // namespace

WatchdogRequest watchdog_request(const char* usec, const char* pid, std::int64_t self) {
  WatchdogRequest r;
  if (usec == nullptr) return r;
  const auto us = parse_count(usec);
  // Microseconds to nanoseconds must fit an int64 (about 292 years).
  if (!us || *us == 0 || *us > static_cast<std::uint64_t>(INT64_MAX / 1000)) {
    r.error = std::string("WATCHDOG_USEC='") + usec + "': expected a positive whole number of microseconds";
    return r;
  }
  if (pid != nullptr) {
    const auto p = parse_count(pid);
    if (!p || *p == 0) {
      r.error = std::string("WATCHDOG_PID='") + pid + "': expected a process id";
      return r;
    }
    if (static_cast<std::int64_t>(*p) != self) return r;  // meant for another process of the unit
  }
  r.timeout_ns = static_cast<std::int64_t>(*us) * 1000;
  r.interval_ns = r.timeout_ns / 2;
  return r;
}

StallRequest stall_request(const char* after) {
  StallRequest r;
  if (after == nullptr) return r;
  r.after = parse_count(after);
  if (!r.after) r.error = std::string("METER_TEST_STALL_AFTER_KEEPALIVES='") + after + "': expected a count";
  return r;
}

bool KeepAlivePacer::due(std::int64_t now_ns) {
  if (interval_ns_ <= 0) return false;
  if (sent_ > 0 && now_ns < next_ns_) return false;
  next_ns_ = now_ns + interval_ns_;
  ++sent_;
  return true;
}

ServiceWatchdog::ServiceWatchdog()
    : request_(watchdog_request(std::getenv("WATCHDOG_USEC"), std::getenv("WATCHDOG_PID"), ::getpid())),
      stall_(stall_request(std::getenv("METER_TEST_STALL_AFTER_KEEPALIVES"))),
      pacer_(request_.interval_ns) {
  error_ = request_.error.empty() ? stall_.error : request_.error;
}

bool ServiceWatchdog::keep_alive_due() {
  if (stall_.after && pacer_.sent() >= *stall_.after) {
    ::pause();  // the stalled loop: no keep-alive until the manager's signal (or SIGTERM) comes
    return false;
  }
  return pacer_.due(monotonic_now_ns());
}

}  // namespace meter::protocol
