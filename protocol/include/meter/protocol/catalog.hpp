// The signal catalog: every value the controller can send and the view can show.
//
// The catalog is data: a COVESA VSS JSON file (the form `vspec export json` writes) read by
// parse_catalog(). The shipped default, protocol/catalog/signals.vss.json, is compiled into the
// library (default_catalog()); `--catalog FILE` on either process replaces it. Its hash travels in
// HELLO so two ends with different catalogs never mis-read each other's ids: the controller either
// sends its catalog to the view or refuses the link (docs/protocol.md, docs/catalog.md).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

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
  SignalId id = 0;    // the leaf's meter_id: stable, never reused, never renumbered
  std::string name;   // the VSS path ("Vehicle.Speed"; Cluster.* where VSS has no equivalent)
  std::string unit;   // the VSS unit ("km/h", "rpm", "percent", "celsius", "km", "")
  double min = 0.0;   // physical range the view is designed for
  double max = 0.0;
  SignalKind kind = SignalKind::Gauge;
  bool operator==(const SignalInfo&) const = default;
};

// A loaded catalog: its entries ordered by id, where it came from and the JSON text it was read
// from (what the controller sends to a view that lacks it).
class Catalog {
 public:
  // Entries in any order; ids and names must be unique (std::invalid_argument otherwise).
  Catalog(std::vector<SignalInfo> signals, std::string source, std::string text);

  std::span<const SignalInfo> signals() const { return signals_; }
  std::size_t size() const { return signals_.size(); }
  const SignalInfo* find(SignalId id) const;         // O(1)
  const SignalInfo* find(std::string_view name) const;
  // Position of `id` in signals(), std::nullopt if absent. O(1).
  std::optional<std::size_t> index_of(SignalId id) const;
  // The entry named `name`; std::runtime_error naming this catalog's source and `needed_for` if
  // absent (the start-up check of a signal some code depends on).
  const SignalInfo& require(std::string_view name, std::string_view needed_for) const;
  // FNV-1a 64 over a canonical text form of every entry (id, name, unit, min, max, kind):
  // descriptions and formatting do not change it.
  std::uint64_t hash() const { return hash_; }
  const std::string& source() const { return source_; }  // file name, or where it was received from
  const std::string& text() const { return text_; }

 private:
  std::vector<SignalInfo> signals_;
  std::vector<std::uint16_t> position_by_id_;
  std::string source_;
  std::string text_;
  std::uint64_t hash_ = 0;
};

struct CatalogParseResult {
  std::shared_ptr<const Catalog> catalog;  // null on error
  std::string error;                       // "FILE: JSON.PATH: what was expected", "" on success
};

// Pure: JSON text -> catalog. Never throws, never crashes on any input; an error names
// `file_name`, the JSON path of the offending value and what was expected there.
CatalogParseResult parse_catalog(std::string_view text, std::string_view file_name);
// Reads and parses a file; std::runtime_error with the parser's message (or the I/O error).
std::shared_ptr<const Catalog> load_catalog_file(const std::string& path);

// The shipped catalog, compiled in from protocol/catalog/signals.vss.json.
std::shared_ptr<const Catalog> default_catalog();

// The catalog this process uses: default_catalog() unless replaced at start-up (`--catalog`) or
// by the view adopting the one its controller sent. Set it before anything holds a SignalTable.
std::shared_ptr<const Catalog> active_catalog();
void set_active_catalog(std::shared_ptr<const Catalog> catalog);
// `--catalog FILE` as both processes take it: "" keeps the default; otherwise the file is loaded
// and made active. Returns the active catalog. std::runtime_error with the loader's message.
std::shared_ptr<const Catalog> use_catalog_option(const std::string& path);

// Shorthands on active_catalog().
std::span<const SignalInfo> catalog();
const SignalInfo* find_signal(SignalId id);
const SignalInfo* find_signal(std::string_view name);
std::uint64_t catalog_hash();

std::string_view to_string(SignalKind kind);
std::optional<SignalKind> kind_from_string(std::string_view text);
std::string_view to_string(SignalStatus status);
std::optional<SignalStatus> status_from_string(std::string_view text);

// VSS names of the signals some code treats specially (the controller's odometer and trip, the
// speed that drives them, the ignition). Looked up by name in the loaded catalog at start-up.
namespace vss {
inline constexpr std::string_view kSpeed = "Vehicle.Speed";
inline constexpr std::string_view kOdometer = "Vehicle.TraveledDistance";
inline constexpr std::string_view kTrip = "Vehicle.TripMeterReading";
inline constexpr std::string_view kIgnition = "Vehicle.LowVoltageSystemState";
}  // namespace vss

// Ids of the shipped default catalog (its meter_id fields), for tests and tools that are built
// against it. Product code finds a signal by name in the loaded catalog instead: another catalog
// may number it differently.
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
