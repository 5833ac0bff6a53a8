// The controller's notifications to its service manager (systemd, docs/deploy.md): ready once the
// link listens, a keep-alive from the run loop, stopping at the end. Without NOTIFY_SOCKET every
// call does nothing, so the controller behaves as it does outside a service.
#pragma once

#include <ostream>
#include <string>

#include "meter/protocol/service_notifier.hpp"

namespace meter::controller {

class ControllerService {
 public:
  explicit ControllerService(std::ostream& err);
  // READY=1 with the endpoint views connect to as the unit's status line.
  void listening(const std::string& endpoint) { notifier_.ready("publishing on " + endpoint); }
  // A keep-alive when one is due (a turn of the run loop).
  void alive() { notifier_.alive(); }
  void stopping() { notifier_.stopping(); }

 private:
  protocol::ServiceNotifier notifier_;
};

}  // namespace meter::controller
