// The child side of the SIGKILL endurance runs (controller/tests/persistence_odometer_store_test.cpp: 220 kills in
// the suite; bench/controller/odometer_kill_bench.cpp: thousands): integrate 100 km/h in 1 ms steps,
// announce each total on `announce_fd` BEFORE persisting it (so the parent knows the truth at the
// instant of the kill), persist every `persist_every` steps, until killed. Never returns.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <string>

#include "meter/controller/conditioning/odometer.hpp"
#include "meter/controller/persistence/odometer_store.hpp"

namespace meter::controller::testing {

[[noreturn]] inline void run_odometer_writer(const std::string& dir, int announce_fd, int persist_every) {
  try {
    OdometerStore store(dir);
    Odometer odo;
    const OdometerLoad loaded = store.load();
    if (loaded.state == OdometerState::Refused) ::_exit(4);  // a refused start: the parent counts it
    if (loaded.record) odo.set(loaded.record->odo_um, loaded.record->trip_um);
    for (int i = 1;; ++i) {
      odo.add_speed(100.0, 1000000);
      const std::int64_t now = odo.total_um();
      if (::write(announce_fd, &now, sizeof now) != sizeof now) ::_exit(3);
      if (i % persist_every == 0) store.save(odo.total_um(), odo.trip_um());
    }
  } catch (...) {
    ::_exit(2);  // a store error: the parent sees the child die without being killed
  }
}

}  // namespace meter::controller::testing
