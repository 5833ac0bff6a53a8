// The signal catalog: every value the controller can send and the view can show.
// Both processes are built from this one table; its hash travels in HELLO so two builds with
// different catalogs refuse to talk instead of mis-reading each other's ids.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace meter::protocol {

using SignalId = std::uint16_t;

enum class SignalKind : std::uint8_t {
  Gauge = 0,     // continuous value drawn by a needle, bar or number
  Enum = 1,      // small integer state (gear, ignition state)
  Telltale = 2,  // lamp: 0 = off, 1 = on (the controller resolves blinking and rules)
  Counter = 3,   // monotonic accumulated value (odometer, trip)
  Text = 4,      // short UTF-8 text
};

enum class SignalStatus : std::uint8_t {
  Valid = 0,
  TimedOut = 1,      // source stopped sending within its timeout
  Invalid = 2,       // source sent something unusable (out of range, NaN, sender fault)
  NotAvailable = 3,  // no source configured or nothing received yet
};

struct SignalInfo {
  SignalId id;             // stable: never reused, never renumbered
  std::string_view name;   // COVESA VSS name where one exists, Cluster.* otherwise
  std::string_view unit;   // SI-ish display unit ("km/h", "rpm", "percent", "celsius", "km", "")
  double min;              // physical range the view is designed for
  double max;
  SignalKind kind;
};

// All catalog entries, ordered by id.
std::span<const SignalInfo> catalog();
const SignalInfo* find_signal(SignalId id);
const SignalInfo* find_signal(std::string_view name);
// FNV-1a 64 over a canonical text form of every entry (id, name, unit, min, max, kind).
std::uint64_t catalog_hash();

std::string_view to_string(SignalKind kind);
std::string_view to_string(SignalStatus status);
std::optional<SignalStatus> status_from_string(std::string_view text);

// Well-known ids, for code that must refer to a specific signal.
namespace sig {
inline constexpr SignalId kSpeed = 1;
inline constexpr SignalId kEngineSpeed = 2;
inline constexpr SignalId kFuelLevel = 3;
inline constexpr SignalId kCoolantTemp = 4;
inline constexpr SignalId kCurrentGear = 5;
inline constexpr SignalId kOdometer = 6;
inline constexpr SignalId kTrip = 7;
inline constexpr SignalId kOutsideTemp = 8;
inline constexpr SignalId kIgnition = 9;
inline constexpr SignalId kTurnLeft = 20;
inline constexpr SignalId kTurnRight = 21;
inline constexpr SignalId kHighBeam = 22;
inline constexpr SignalId kLowBeam = 23;
inline constexpr SignalId kFrontFog = 24;
inline constexpr SignalId kParkingBrake = 25;
inline constexpr SignalId kBrakeFault = 26;
inline constexpr SignalId kAbs = 27;
inline constexpr SignalId kAirbag = 28;
inline constexpr SignalId kSeatBelt = 29;
inline constexpr SignalId kOilPressure = 30;
inline constexpr SignalId kBattery = 31;
inline constexpr SignalId kCheckEngine = 32;
inline constexpr SignalId kCoolantOverTemp = 33;
inline constexpr SignalId kEsc = 34;
inline constexpr SignalId kTpms = 35;
inline constexpr SignalId kFuelLow = 36;
}  // namespace sig

}  // namespace meter::protocol
