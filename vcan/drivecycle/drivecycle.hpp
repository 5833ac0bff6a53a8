// The demo drive cycle: a deterministic ~60 s scenario for the demo vehicle, encoded with the
// controller's DBC encoder into a candump -L log. The scenario is a pure function of time so the
// test can check the decoded log against the intended profile.
#pragma once

#include <cstdint>
#include <string>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"

namespace meter::drivecycle {

struct VehicleState {
  double speed_kmh;
  double rpm;
  int gear;  // 0 neutral, 1..6, 15 park
  int ignition;  // DBC: 0 off, 1 acc, 2 on, 3 start
  bool engine_running;
  bool turn_left, turn_right, high_beam, low_beam, parking_brake, belt_unbuckled, oil_pressure_low, brake_pedal;
  double coolant_c, fuel_percent, outside_c, throttle;
  // Cluster settings (HU_ClusterSettings): the display features at known times.
  int units;        // DBC UNITS: 1 km, 2 miles
  bool fahrenheit;  // with miles
  bool night;
  double brightness;  // percent
  int page;           // 0 drive, 1 trip computer
};

constexpr double kDurationS = 60.0;
constexpr std::int64_t kStartNs = 1767225600LL * 1000000000LL;  // 2026-01-01T00:00:00Z

// Display features: trip-computer page 41..46 s, miles/mph and °F 46..52 s, night from 52 s,
// brightness 40 % from 56 s (100 % before); the sweep runs at ignition on (the first frames) and
// the shift light is lit while cruising at 130 km/h in 6th (above 3000 rpm, about 28..44 s).
// Speed profile: idle until 8 s, accelerate to 130 km/h by 30 s, cruise to 42 s, brake to a stop by 55 s.
double speed_at(double t_s);
VehicleState state_at(double t_s);

// Writes the whole log. Throws if the DBC lacks a message/signal the scenario needs.
std::string generate_log(const meter::controller::Database& db, double duration_s = kDurationS,
                         const std::string& interface = "vcan0");

}  // namespace meter::drivecycle
