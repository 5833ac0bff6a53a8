#include "service_notify.hpp"

#include <systemd/sd-daemon.h>

namespace meter::controller {

ControllerService::ControllerService(std::ostream& err)
    : notifier_([](const std::string& state) { sd_notify(0, state.c_str()); }, err, "meter-controller") {}

}  // namespace meter::controller
