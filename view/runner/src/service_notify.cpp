#include "meter/runner/service_notify.hpp"

#include <systemd/sd-daemon.h>

namespace meter::runner {

ViewService::ViewService(std::ostream& log)
    : notifier_([](const std::string& state) { sd_notify(0, state.c_str()); }, log, "meter-view") {}

void ViewService::frame_drawn() {
  if (!ready_) {
    ready_ = true;
    notifier_.ready("drawing the live link's frames");
  }
  notifier_.alive();
}

}  // namespace meter::runner
