// The --input [NAME=]TARGET and --dbc [NAME=]FILE arguments paired into one spec per input.
#pragma once

#include <string>
#include <vector>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/run/input_schemes.hpp"

namespace meter::controller {

// One --input and its DBC.
struct InputSpec {
  std::string name;    // empty: the only input, unnamed
  std::string target;  // SCHEME:ADDRESS, as given: log:FILE | can:IFACE | modbus-tcp:HOST:PORT | ...
  std::string dbc;     // empty: none
  const InputScheme* scheme = nullptr;  // the registry's entry for the target's scheme (never null once parsed)
  std::string address;                  // the target after "SCHEME:"

  InputKind kind() const { return scheme->kind; }
};

// Pairs every --input [NAME=]TARGET with its --dbc [NAME=]FILE. One input needs no name (and takes
// an unnamed --dbc); with several, each input has a distinct name and each --dbc names its input.
// Throws std::invalid_argument naming the option and what was expected: a missing, repeated or
// reserved name, a --dbc for no input or a second one for the same input, a CAN input among
// several without a DBC, a DBC on a Modbus input among several.
std::vector<InputSpec> parse_input_specs(const std::vector<std::string>& inputs, const std::vector<std::string>& dbcs);

// Pairs the Modbus inputs with the mapping's register tables: one Modbus input may read the
// [modbus] table; with several, each reads its own [modbus NAME] table. Throws
// std::invalid_argument naming the input or the table: a Modbus input among several without its
// table, a [modbus NAME] table (while any Modbus input is given) that no Modbus input is named for.
void check_modbus_tables(const std::vector<InputSpec>& specs, const Mapping& map);

}  // namespace meter::controller
