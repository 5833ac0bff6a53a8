#include "meter/protocol/service_notifier.hpp"

#include <utility>

#include "meter/protocol/log/logger.hpp"

namespace meter::protocol {

ServiceNotifier::ServiceNotifier(Send send, std::ostream& log, std::string_view program) : send_(std::move(send)) {
  if (!watchdog_.error().empty())
    LogLine(log, LogLevel::Warning, "service") << program << ": " << watchdog_.error() << "; no watchdog keep-alives\n";
}

void ServiceNotifier::ready(std::string_view status) { send_("READY=1\nSTATUS=" + std::string(status)); }

void ServiceNotifier::alive() {
  if (watchdog_.keep_alive_due()) send_("WATCHDOG=1");
}

void ServiceNotifier::stopping() { send_("STOPPING=1\nSTATUS=stopping"); }

}  // namespace meter::protocol
