#include "meter/runner/service_notify.hpp"
#include "meter/protocol/log/logger.hpp"

#include <systemd/sd-daemon.h>

namespace meter::runner {

ViewService::ViewService(std::ostream& log) {
  if (!watchdog_.error().empty()) protocol::LogLine(log, protocol::LogLevel::Warning, "service") << "meter-view: " << watchdog_.error() << "; no watchdog keep-alives\n";
}

void ViewService::frame_drawn() {
  if (!ready_) {
    ready_ = true;
    sd_notify(0, "READY=1\nSTATUS=drawing the live link's frames");
  }
  if (watchdog_.keep_alive_due()) sd_notify(0, "WATCHDOG=1");
}

void ViewService::stopping() { sd_notify(0, "STOPPING=1\nSTATUS=stopping"); }

}  // namespace meter::runner
