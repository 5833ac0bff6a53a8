// The view's notifications to its service manager (systemd, docs/deploy.md): ready once the first
// live frame is drawn, a keep-alive from the live loop, stopping at the end. Without NOTIFY_SOCKET
// every call does nothing, so the view behaves as it does outside a service.
#pragma once

#include <ostream>

#include "meter/protocol/service_notifier.hpp"

namespace meter::runner {

class ViewService {
 public:
  explicit ViewService(std::ostream& log);
  // After each turn of the live loop: READY=1 after the first, then keep-alives as they fall due.
  void frame_drawn();
  void stopping() { notifier_.stopping(); }

 private:
  protocol::ServiceNotifier notifier_;
  bool ready_ = false;
};

}  // namespace meter::runner
