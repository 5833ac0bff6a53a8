// odometer-reset: a workshop's explicit "this is the odometer" for a refused odometer state.
#include <cmath>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>

#include "command_output.hpp"
#include "meter/controller/persistence/odometer_store.hpp"
#include "meter/controller/run/odometer_reset_command.hpp"

namespace meter::controller {

int odometer_reset_command(const std::string& state_dir, std::optional<double> km, std::ostream& out, std::ostream& err) {
  try {
    OdometerStore store(state_dir);
    const OdometerLoad before = store.load();
    for (const std::string& fault : before.faults) out << "found: " << fault << "\n";
    OdometerRecord r;
    if (km) {
      if (!std::isfinite(*km) || *km < 0 || *km > 9.0e9)
        throw std::runtime_error("--km: expected a distance in km, 0 .. 9e9, got " + fmt_double(*km));
      r.odo_um = static_cast<std::int64_t>(std::llround(*km * 1e9));
    } else if (auto best = store.best_valid()) {
      r = *best;
    } else {
      throw std::runtime_error(state_dir + ": no valid odometer copy to restore; give the distance with --km");
    }
    store.reset(r.odo_um, r.trip_um);
    out << "odometer in " << state_dir << " reset to " << fmt_double(static_cast<double>(r.odo_um) / 1e9) << " km\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-controller: odometer-reset: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
