#include "meter/protocol/catalog.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>

namespace meter::protocol {
namespace {

using K = SignalKind;

// Append-only. A new signal takes a new id; a retired one keeps its id forever.
// Gauges carry COVESA VSS names (VSS 4.0); lamp states have no VSS equivalent (VSS models the
// cause, e.g. Vehicle.ADAS.ABS.IsError, not the lamp) so they live under Cluster.Telltale.
constexpr std::array kCatalog{
    SignalInfo{sig::kSpeed, "Vehicle.Speed", "km/h", 0.0, 300.0, K::Gauge},
    SignalInfo{sig::kEngineSpeed, "Vehicle.Powertrain.CombustionEngine.Speed", "rpm", 0.0, 10000.0, K::Gauge},
    SignalInfo{sig::kFuelLevel, "Vehicle.Powertrain.FuelSystem.RelativeLevel", "percent", 0.0, 100.0, K::Gauge},
    SignalInfo{sig::kCoolantTemp, "Vehicle.Powertrain.CombustionEngine.ECT", "celsius", -40.0, 150.0, K::Gauge},
    // VSS CurrentGear: -1 reverse, 0 neutral, 1..8 forward; 126 park, 127 drive (as VSS SelectedGear).
    SignalInfo{sig::kCurrentGear, "Vehicle.Powertrain.Transmission.CurrentGear", "", -1.0, 127.0, K::Enum},
    SignalInfo{sig::kOdometer, "Vehicle.TraveledDistance", "km", 0.0, 9999999.0, K::Counter},
    SignalInfo{sig::kTrip, "Vehicle.TripMeterReading", "km", 0.0, 99999.9, K::Counter},
    SignalInfo{sig::kOutsideTemp, "Vehicle.Exterior.AirTemperature", "celsius", -40.0, 85.0, K::Gauge},
    // VSS LowVoltageSystemState as a number: 0 undefined, 1 lock, 2 off, 3 acc, 4 on, 5 start.
    SignalInfo{sig::kIgnition, "Vehicle.LowVoltageSystemState", "", 0.0, 5.0, K::Enum},
    SignalInfo{sig::kTurnLeft, "Cluster.Telltale.TurnLeft", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kTurnRight, "Cluster.Telltale.TurnRight", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kHighBeam, "Cluster.Telltale.HighBeam", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kLowBeam, "Cluster.Telltale.LowBeam", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kFrontFog, "Cluster.Telltale.FrontFog", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kParkingBrake, "Cluster.Telltale.ParkingBrake", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kBrakeFault, "Cluster.Telltale.BrakeFault", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kAbs, "Cluster.Telltale.ABS", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kAirbag, "Cluster.Telltale.Airbag", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kSeatBelt, "Cluster.Telltale.SeatBelt", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kOilPressure, "Cluster.Telltale.OilPressure", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kBattery, "Cluster.Telltale.Battery", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kCheckEngine, "Cluster.Telltale.CheckEngine", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kCoolantOverTemp, "Cluster.Telltale.CoolantTemp", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kEsc, "Cluster.Telltale.ESC", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kTpms, "Cluster.Telltale.TPMS", "", 0.0, 1.0, K::Telltale},
    SignalInfo{sig::kFuelLow, "Cluster.Telltale.FuelLow", "", 0.0, 1.0, K::Telltale},
};

constexpr bool ids_strictly_increasing() {
  for (std::size_t i = 1; i < kCatalog.size(); ++i) {
    if (kCatalog[i].id <= kCatalog[i - 1].id) return false;
  }
  return true;
}
static_assert(ids_strictly_increasing(), "catalog ids must be unique and sorted");

}  // namespace

std::span<const SignalInfo> catalog() { return kCatalog; }

const SignalInfo* find_signal(SignalId id) {
  auto it = std::lower_bound(kCatalog.begin(), kCatalog.end(), id,
                             [](const SignalInfo& s, SignalId v) { return s.id < v; });
  return (it != kCatalog.end() && it->id == id) ? &*it : nullptr;
}

const SignalInfo* find_signal(std::string_view name) {
  for (const auto& s : kCatalog) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::uint64_t catalog_hash() {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix = [&h](std::string_view text) {
    for (unsigned char c : text) {
      h ^= c;
      h *= 0x100000001b3ULL;
    }
  };
  for (const auto& s : kCatalog) {
    char numbers[96];
    // %.17g round-trips doubles exactly, so the text form is canonical.
    std::snprintf(numbers, sizeof numbers, "%u|%.17g|%.17g|%u", static_cast<unsigned>(s.id), s.min,
                  s.max, static_cast<unsigned>(s.kind));
    mix(numbers);
    mix("|");
    mix(s.name);
    mix("|");
    mix(s.unit);
    mix("\n");
  }
  return h;
}

std::string_view to_string(SignalKind kind) {
  switch (kind) {
    case SignalKind::Gauge: return "gauge";
    case SignalKind::Enum: return "enum";
    case SignalKind::Telltale: return "telltale";
    case SignalKind::Counter: return "counter";
    case SignalKind::Text: return "text";
  }
  return "unknown";
}

std::string_view to_string(SignalStatus status) {
  switch (status) {
    case SignalStatus::Valid: return "valid";
    case SignalStatus::TimedOut: return "timed-out";
    case SignalStatus::Invalid: return "invalid";
    case SignalStatus::NotAvailable: return "not-available";
  }
  return "unknown";
}

std::optional<SignalStatus> status_from_string(std::string_view text) {
  for (auto s : {SignalStatus::Valid, SignalStatus::TimedOut, SignalStatus::Invalid,
                 SignalStatus::NotAvailable}) {
    if (to_string(s) == text) return s;
  }
  return std::nullopt;
}

}  // namespace meter::protocol
