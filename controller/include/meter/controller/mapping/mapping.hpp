// The mapping file: which bus signals (DBC "Message.Signal") or Modbus registers feed which catalog
// signal, with unit conversion, timeouts and conditioning. Format: docs/mapping.md. Its parser
// (parse_mapping, load_mapping): mapping/map_file.hpp, included here. Applying it to source
// values: mapping/apply.hpp; the conditioning parameters it carries: conditioning/.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/conditioning/fuel.hpp"
#include "meter/controller/conditioning/needle.hpp"
#include "meter/controller/conditioning/telltales.hpp"
#include "meter/controller/e2e/e2e_config.hpp"
#include "meter/controller/input/modbus_registers.hpp"
#include "meter/controller/mapping/map_file.hpp"
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
  // DBC value names (VAL_) in `map` and `lit_when`: name -> catalog value, turned into remap
  // entries against the DBC at start-up (mapping/value_names.hpp).
  struct NamedValue {
    std::string name;
    double to;
    int line;
  };
  std::vector<NamedValue> remap_names;
  std::optional<double> remap_default;  // the catalog value of a source no remap entry matches
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

struct Mapping {
  std::string file;
  double bulb_check_s = 3.0;
  double persist_interval_s = 5.0;
  double update_period_s = 0.01;  // model tick
  std::vector<OutputMapping> outputs;
  std::optional<ModbusConfig> modbus;  // [modbus] and [modbus.register NAME]: the one Modbus input's table
  // [modbus INPUT] and [modbus.register INPUT.NAME]: the table of the Modbus input named INPUT
  // (--input INPUT=modbus-...), for several Modbus inputs at once.
  std::map<std::string, ModbusConfig, std::less<>> modbus_inputs;
  E2eSettings e2e;  // [e2e] and [e2e MESSAGE] sections: the CAN end-to-end checks
  const OutputMapping* find(protocol::SignalId id) const;
  // The table a "modbus.NAME" or "modbus.INPUT.NAME" source reads from, if it defines that register.
  const ModbusConfig* modbus_table_of(std::string_view source) const;
};

}  // namespace meter::controller
