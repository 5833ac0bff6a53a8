// The mapping file: which bus signals (DBC "Message.Signal") or Modbus registers feed which catalog
// signal, with unit conversion, timeouts and conditioning. Format: docs/mapping.md.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/conditioning.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::controller {

class MappingError : public std::runtime_error {
 public:
  MappingError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what), line_(line) {}
  int line() const { return line_; }

 private:
  int line_;
};

enum class Combine : std::uint8_t { First, Mean, Min, Max };
enum class TimeoutAction : std::uint8_t { Hold, Substitute, Invalid };
enum class RangeAction : std::uint8_t { Invalid, Clamp, Accept };
enum class Rule : std::uint8_t { None, SeatBelt, Below, Above };
enum class Accumulate : std::uint8_t { None, Speed, Counter };

struct OutputMapping {
  protocol::SignalId id = 0;
  std::string name;  // catalog name
  int line = 0;
  std::vector<std::string> sources;  // "Message.Signal" or "modbus.NAME"
  Combine combine = Combine::First;
  double scale = 1.0, offset = 0.0;  // catalog value = source * scale + offset
  std::vector<std::pair<double, double>> remap;  // exact source value -> catalog value (enums)
  RangeAction out_of_range = RangeAction::Invalid;
  bool timeout_auto = true;                        // derive from the DBC cycle time
  std::optional<double> timeout_s, first_timeout_s;
  TimeoutAction on_timeout = TimeoutAction::Invalid;
  double substitute = 0.0;
  double needle_tau_s = 0.0;  // > 0: critically damped needle
  bool fuel = false;
  FuelFilterConfig fuel_config;
  std::optional<SpeedometerRule> speedometer;
  std::optional<BlinkPattern> blink;  // telltale flashes while requested
  bool invert = false;                // telltale lit when the source is 0
  Rule rule = Rule::None;
  std::string rule_input;  // catalog name whose displayed value the Below/Above rule watches
  double rule_on = 0, rule_off = 0;
  SeatBeltConfig seat_belt;
  Accumulate accumulate = Accumulate::None;
  unsigned counter_bits = 16;
  double um_per_count = 0;
};

enum class RegisterType : std::uint8_t { Int16, Uint16, Int32, Uint32, Float32 };
struct ModbusRegister {
  std::string name;
  bool input_table = false;  // false: holding registers (FC 3), true: input registers (FC 4)
  int address = 0;
  RegisterType type = RegisterType::Uint16;
  bool word_swap = false;  // 32-bit values: low word first
  double scale = 1.0, offset = 0.0;
  int line = 0;
  int words() const { return type == RegisterType::Int16 || type == RegisterType::Uint16 ? 1 : 2; }
};
struct ModbusConfig {
  double poll_s = 0.1;
  double response_timeout_s = 0.2;
  int unit_id = 1;
  std::string heartbeat;      // register name that must keep changing; empty = none
  int stale_after_polls = 5;  // heartbeat unchanged for this many polls = all signals invalid
  std::vector<ModbusRegister> registers;
  const ModbusRegister* find(std::string_view name) const;
};

struct Mapping {
  std::string file;
  double bulb_check_s = 3.0;
  double persist_interval_s = 5.0;
  double update_period_s = 0.01;  // model tick
  std::vector<OutputMapping> outputs;
  std::optional<ModbusConfig> modbus;
  const OutputMapping* find(protocol::SignalId id) const;
};

Mapping parse_mapping(std::string_view text, const std::string& file = "<map>");
Mapping load_mapping(const std::string& path);

// Decodes a Modbus register value from raw 16-bit words (big-endian words, as on the wire).
double modbus_register_value(const ModbusRegister& r, const std::uint16_t* words);

}  // namespace meter::controller
