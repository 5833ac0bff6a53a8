// The input registry: every --input scheme (the text before the first ':' of log:FILE, can:IFACE,
// modbus-tcp:HOST:PORT, ...) with the kind of input it names and what opens it. A target's scheme
// is parsed here and nowhere else; a new input backend is one entry in input_schemes().
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/input.hpp"
#include "meter/controller/input/log_source.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"

namespace meter::controller {

enum class InputKind : std::uint8_t {
  Log,     // a recorded file: loaded whole, merged with the other logs, replayed on the log's clock
  CanBus,  // a live CAN bus: its frames decoded with its input's DBC
  Modbus,  // live register values: the mapping's [modbus] table (several inputs: [modbus INPUT] each), no DBC
};

// What opening a live input may use: its address (the target after "scheme:"), its input index and
// name ("" when unnamed), its DBC (none: nullptr), and the mapping and model (the ids it reads
// there: kernel filters; a Modbus input's register table).
struct LiveInputContext {
  std::string address;
  int index = 0;
  std::string name;
  const Database* db = nullptr;
  const Mapping& map;
  const Model& model;
};

struct InputScheme {
  std::string_view scheme;  // "can" in can:vcan0
  std::string_view form;    // "can:IFACE": the help text and the errors list these
  std::string_view what;    // "SocketCAN, e.g. can:vcan0": the help text
  InputKind kind;
  // Log: the file as a source of its frames, in the format log_format.hpp finds for it, read as
  // the replay asks. Other kinds: nullptr.
  std::unique_ptr<LogSource> (*load)(const std::string& address) = nullptr;
  // Live kinds: the opened input; throws when it cannot be opened. Log: nullptr (the logs are
  // merged and replayed as one input).
  std::unique_ptr<Input> (*open)(const LiveInputContext& context) = nullptr;
};

// Every scheme this build opens.
std::span<const InputScheme> input_schemes();

struct InputTarget {
  const InputScheme* scheme = nullptr;
  std::string address;  // the target after "scheme:", not empty
};
// Splits "scheme:address" at its first ':' and finds the scheme. Throws std::invalid_argument with
// the target and every accepted form when the scheme is unknown or the address is empty.
InputTarget parse_input_target(const std::string& target);

// "log:FILE, can:IFACE, modbus-tcp:HOST:PORT or modbus-rtu:DEV:BAUD[:8N1]"
std::string input_forms();
// "log:FILE (a recorded CAN log: candump), can:IFACE (SocketCAN, e.g. can:vcan0), ...": the help.
std::string input_forms_described();

}  // namespace meter::controller
