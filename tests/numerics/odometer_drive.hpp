// Shared by the unit (10,000 km) and slow (1,000,000 km) odometer cases.
#pragma once

#include <cstdint>

#include "meter/controller/conditioning/odometer.hpp"

namespace meter::numerics {

// Drives `steps` 10 ms steps at a speed profile with 0.01 km/h resolution around `mean_kmh`, and
// returns (odometer um, exact um as an integer sum, naive double km accumulator).
struct OdoRun {
  std::int64_t odo_um = 0, exact_um = 0;
  double naive_km = 0;
};
inline OdoRun drive(std::int64_t steps, std::int64_t mean_centi_kmh) {
  controller::Odometer o;
  OdoRun r;
  std::int64_t exact_units = 0;  // km/h * ns, exact (3.6e18 at 1,000,000 km: fits int64)
  double naive = 0;
  for (std::int64_t i = 0; i < steps; ++i) {
    const std::int64_t centi = mean_centi_kmh + (i % 2001) - 1000;  // +-10 km/h sawtooth
    const double kmh = static_cast<double>(centi) / 100.0;
    o.add_speed(kmh, 10'000'000);
    exact_units += centi * 100'000;  // centi/100 km/h * 1e7 ns
    naive += kmh * (0.01 / 3600.0);
  }
  r.odo_um = o.total_um();
  r.exact_um = static_cast<std::int64_t>(exact_units / 3600);
  r.naive_km = naive;
  return r;
}

}  // namespace meter::numerics
