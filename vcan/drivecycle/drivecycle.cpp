#include "drivecycle.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "meter/controller/input/candump_line.hpp"

namespace meter::drivecycle {
namespace {

double smoothstep(double a, double b, double t) {
  double x = std::clamp((t - a) / (b - a), 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Shift points (km/h) and engine rpm per km/h in each gear.
constexpr double kUpshift[] = {0, 18, 35, 55, 80, 105};
constexpr double kRpmPerKmh[] = {0, 118, 68, 46, 35, 28, 23.5};

// Deterministic jitter: a fixed LCG, so the log is byte-identical on every run.
struct Lcg {
  std::uint64_t s;
  double next() {  // [0, 1)
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  }
};

}  // namespace

double speed_at(double t) {
  if (t < 8) return 0;
  if (t < 30) return 130.0 * smoothstep(8, 30, t);
  if (t < 42) return 130.0;
  if (t < 55) return 130.0 * (1.0 - smoothstep(42, 55, t));
  return 0;
}

VehicleState state_at(double t) {
  VehicleState s{};
  s.speed_kmh = speed_at(t);
  s.ignition = t < 1.0 ? 2 : t < 1.6 ? 3 : 2;
  s.engine_running = t >= 1.6;
  s.gear = 15;
  if (t >= 6.5) {
    s.gear = 1;
    for (int g = 1; g <= 5; ++g)
      if (s.speed_kmh >= kUpshift[g]) s.gear = g + 1;
  }
  if (t >= 56) s.gear = 15;
  if (s.speed_kmh == 0 && t >= 55 && t < 56) s.gear = 0;
  if (!s.engine_running) s.rpm = t >= 1.0 ? 250 : 0;  // cranking
  else if (s.gear >= 1 && s.gear <= 6) s.rpm = std::max(800.0, s.speed_kmh * kRpmPerKmh[s.gear]);
  else s.rpm = 800;
  if (s.engine_running && t < 4) s.rpm = 800 + 500 * (1 - smoothstep(1.6, 4, t));  // cold-start flare
  s.throttle = (t >= 8 && t < 30) ? 40 + 30 * std::sin(t) * 0.5 : (t >= 30 && t < 42 ? 22 : 0);
  s.turn_left = t >= 33 && t < 37;
  s.turn_right = t >= 38.5 && t < 42;
  s.low_beam = true;
  s.high_beam = t >= 31 && t < 33;
  s.parking_brake = t < 7 || t >= 57;
  s.belt_unbuckled = t < 9;  // the driver buckles up only after moving off: seat-belt reminder
  s.oil_pressure_low = (t >= 47 && t < 50) || !s.engine_running;  // warning event while braking
  s.brake_pedal = t >= 42 && t < 56;
  s.coolant_c = 60 + 28 * smoothstep(0, 60, t);
  s.outside_c = 18.5;
  s.fuel_percent = 34.0 - 0.02 * t;
  // After 40 s: the vcan end-to-end test replays 0..40 s and judges the km/h day drive page.
  s.page = t >= 41 && t < 46 ? 1 : 0;
  s.units = t >= 46 && t < 52 ? 2 : 1;
  s.fahrenheit = s.units == 2;
  s.night = t >= 52;
  s.brightness = t >= 56 ? 40 : 100;
  return s;
}

std::string generate_log(const controller::Database& db, double duration_s, const std::string& iface) {
  struct Msg {
    const char* name;
    const controller::DbcMessage* m;
    std::int64_t period_ns, next_ns;
  };
  std::vector<Msg> msgs;
  for (const char* n : {"ECM_EngineStatus", "ESP_WheelSpeeds", "TCM_Gear", "ECM_Temperatures", "BCM_Lights",
                        "FLS_FuelLevel", "ACU_Status", "ENV_Ambient", "HU_ClusterSettings"}) {
    const controller::DbcMessage* m = db.find(n);
    if (!m) throw std::invalid_argument(std::string("drive cycle: the DBC has no message ") + n);
    if (!m->cycle_time_ms) throw std::invalid_argument(std::string("drive cycle: message ") + n + " has no cycle time");
    std::int64_t period = static_cast<std::int64_t>(*m->cycle_time_ms) * 1000000;
    // Stagger the first transmissions as real ECUs do after wake-up.
    msgs.push_back({n, m, period, kStartNs + static_cast<std::int64_t>(msgs.size()) * 1300000});
  }
  Lcg rng{0x6d65746572ULL};
  // The cluster settings draw their jitter from their own generator, so adding them left every
  // other frame of the log byte for byte as it was.
  Lcg settings_rng{0x7365747473ULL};
  std::string out;
  const std::int64_t end = kStartNs + static_cast<std::int64_t>(duration_s * 1e9);
  std::uint8_t alive = 0;
  double pulses_m = 0;  // distance for the 0.2 m pulse counter
  std::int64_t last_pulse_t = kStartNs;
  for (;;) {
    auto it = std::min_element(msgs.begin(), msgs.end(), [](const Msg& a, const Msg& b) { return a.next_ns < b.next_ns; });
    if (it->next_ns >= end) break;
    // Up to +-150 us of transmit jitter, quantised to the microsecond candump prints.
    Lcg& jitter = std::string_view(it->name) == "HU_ClusterSettings" ? settings_rng : rng;
    const std::int64_t t_ns = it->next_ns + static_cast<std::int64_t>((jitter.next() - 0.5) * 300.0) * 1000;
    it->next_ns += it->period_ns;
    const double t = static_cast<double>(t_ns - kStartNs) / 1e9;
    const VehicleState s = state_at(std::max(0.0, t));
    std::vector<std::pair<std::string_view, double>> v;
    auto b = [](bool x) { return x ? 1.0 : 0.0; };
    auto d = [](int x) { return static_cast<double>(x); };
    const std::string name = it->name;
    if (name == "ECM_EngineStatus") {
      v = {{"EngineSpeed", std::round(s.rpm * 4) / 4}, {"EngineRunning", b(s.engine_running)},
           {"OilPressureLow", b(s.oil_pressure_low)}, {"CheckEngine", 0}, {"ChargeWarning", b(!s.engine_running)},
           {"ThrottlePos", std::round(s.throttle / 0.4) * 0.4}, {"AliveCounter", d(alive++ & 15)}};
    } else if (name == "ESP_WheelSpeeds") {
      pulses_m += s.speed_kmh / 3.6 * static_cast<double>(t_ns - last_pulse_t) / 1e9;
      last_pulse_t = t_ns;
      v = {{"VehicleSpeed", s.speed_kmh}, {"WheelSpeedFL", s.speed_kmh}, {"WheelSpeedFR", s.speed_kmh},
           {"ABSFault", 0}, {"ESCFault", 0}, {"BrakeSystemFault", 0}, {"BrakePedal", b(s.brake_pedal)},
           {"DistancePulses", static_cast<double>(static_cast<std::uint64_t>(pulses_m / 0.2) & 0xFF)}};
    } else if (name == "TCM_Gear") {
      v = {{"CurrentGear", d(s.gear)}, {"SelectorPosition", s.gear == 15 ? 0.0 : 3.0}};
    } else if (name == "ECM_Temperatures") {
      v = {{"CoolantTemp", std::round(s.coolant_c)}, {"OilTemp", std::round(s.coolant_c - 5)}, {"CoolantOverTemp", 0}};
    } else if (name == "BCM_Lights") {
      v = {{"TurnLeftReq", b(s.turn_left)}, {"TurnRightReq", b(s.turn_right)}, {"HighBeam", b(s.high_beam)},
           {"LowBeam", b(s.low_beam)}, {"FrontFog", 0}, {"ParkingBrake", b(s.parking_brake)},
           {"DriverBeltUnbuckled", b(s.belt_unbuckled)}, {"IgnitionState", d(s.ignition)}};
    } else if (name == "FLS_FuelLevel") {
      // The sender sloshes while the car accelerates or brakes: +-3 % that the cluster filters out.
      double slosh = s.speed_kmh > 1 ? 3.0 * std::sin(t * 2.1) : 0.0;
      v = {{"FuelLevel", std::round((s.fuel_percent + slosh) * 10) / 10}, {"FuelSenderFault", 0}};
    } else if (name == "ACU_Status") {
      v = {{"AirbagFault", 0}, {"TPMSWarning", 0}};
    } else if (name == "ENV_Ambient") {
      v = {{"OutsideTemp", s.outside_c}};
    } else if (name == "HU_ClusterSettings") {
      v = {{"UNITS", d(s.units)}, {"TempUnit", b(s.fahrenheit)}, {"NightMode", b(s.night)},
           {"ClusterPage", d(s.page)}, {"Brightness", s.brightness}};
    }
    controller::CanFrame f;
    f.timestamp_ns = t_ns;
    f.id = it->m->id;
    f.extended = it->m->extended;
    auto payload = controller::encode(*it->m, v);
    f.len = static_cast<std::uint8_t>(payload.size());
    std::copy(payload.begin(), payload.end(), f.data.begin());
    out += controller::format_candump_line(f, iface);
    out += '\n';
  }
  return out;
}

}  // namespace meter::drivecycle
