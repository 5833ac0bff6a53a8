// The service manager's watchdog, as plain data: what systemd's environment asks of a process
// (WATCHDOG_USEC: the WatchdogSec= of its unit in microseconds; WATCHDOG_PID: the process meant)
// and when the next keep-alive is due. Both processes' notification seams (the controller's run
// loop, the view's live loop) send what this decides; nothing here touches a socket.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace meter::protocol {

// What the environment asks. interval_ns is 0 when no keep-alives are wanted (no WATCHDOG_USEC, or
// one meant for another process); error says why a value set was refused (then no keep-alives).
struct WatchdogRequest {
  std::int64_t timeout_ns = 0;   // WatchdogSec=: the manager restarts the service after this silence
  std::int64_t interval_ns = 0;  // a keep-alive every half of it, as sd_watchdog_enabled(3) advises
  std::string error;
};

// usec and pid are the variables' values (nullptr: unset); self is this process's id.
WatchdogRequest watchdog_request(const char* usec, const char* pid, std::int64_t self);

// The test-only stall (METER_TEST_STALL_AFTER_KEEPALIVES=N, docs/deploy.md): after N keep-alives
// the loop stops as a hung loop would. Unset: never. A value that is not a count is an error.
struct StallRequest {
  std::optional<std::uint64_t> after;
  std::string error;
};
StallRequest stall_request(const char* after);

// Keep-alive pacing on the monotonic clock: one at the first call, then one every interval.
class KeepAlivePacer {
 public:
  explicit KeepAlivePacer(std::int64_t interval_ns) : interval_ns_(interval_ns) {}
  // True when a keep-alive is due at now_ns (and counts it as sent).
  bool due(std::int64_t now_ns);
  std::uint64_t sent() const { return sent_; }

 private:
  std::int64_t interval_ns_;
  std::int64_t next_ns_ = 0;
  std::uint64_t sent_ = 0;
};

// The two requests read from this process's environment, paced: what a loop asks once a turn.
class ServiceWatchdog {
 public:
  // Reads WATCHDOG_USEC, WATCHDOG_PID and METER_TEST_STALL_AFTER_KEEPALIVES; a refused value is
  // described in error() and asks for nothing.
  ServiceWatchdog();
  const std::string& error() const { return error_; }
  std::int64_t timeout_ns() const { return request_.timeout_ns; }
  // True when a keep-alive is due now. Once the test-only stall's count of keep-alives has been
  // sent, the call blocks as a hung loop would, until a signal is handled, then says false.
  bool keep_alive_due();

 private:
  WatchdogRequest request_;
  StallRequest stall_;
  KeepAlivePacer pacer_;
  std::string error_;
};

}  // namespace meter::protocol
