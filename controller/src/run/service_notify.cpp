#include "service_notify.hpp"
#include "meter/protocol/log/logger.hpp"

#include <systemd/sd-daemon.h>

namespace meter::controller {

ControllerService::ControllerService(std::ostream& err) {
  if (!watchdog_.error().empty()) protocol::LogLine(err, protocol::LogLevel::Warning, "service") << "meter-controller: " << watchdog_.error() << "; no watchdog keep-alives\n";
}

void ControllerService::listening(const std::string& endpoint) {
  sd_notify(0, ("READY=1\nSTATUS=publishing on " + endpoint).c_str());
}

void ControllerService::alive() {
  if (watchdog_.keep_alive_due()) sd_notify(0, "WATCHDOG=1");
}

void ControllerService::stopping() { sd_notify(0, "STOPPING=1\nSTATUS=stopping"); }

}  // namespace meter::controller
