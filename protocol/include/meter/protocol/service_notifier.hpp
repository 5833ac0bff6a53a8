// A process's notifications to its service manager (systemd, docs/deploy.md), shared by the
// controller's and the view's seams: READY=1 with the unit's status line, WATCHDOG=1 as the
// watchdog's pacing falls due, STOPPING=1. The message goes out through `send` (sd_notify in the
// processes, which link libsystemd; a recorder in the tests): this library needs no libsystemd.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <string_view>

#include "meter/protocol/service_watchdog.hpp"

namespace meter::protocol {

class ServiceNotifier {
 public:
  using Send = std::function<void(const std::string& state)>;
  // Reads the watchdog's environment; a refused value is logged on `log` as a warning of `program`
  // ("meter-view: WATCHDOG_USEC ...; no watchdog keep-alives") and asks for no keep-alives.
  ServiceNotifier(Send send, std::ostream& log, std::string_view program);
  // READY=1 and STATUS=status.
  void ready(std::string_view status);
  // WATCHDOG=1 when a keep-alive is due (once a turn of the process's loop).
  void alive();
  // STOPPING=1 and STATUS=stopping.
  void stopping();

 private:
  Send send_;
  ServiceWatchdog watchdog_;
};

}  // namespace meter::protocol
