// What the Modbus input reads: the register table (address, type, word order, scale) and the poll
// settings, as plain data. The mapping file's [modbus] sections fill it in; the input needs nothing else.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace meter::controller {

enum class RegisterType : std::uint8_t { Int16, Uint16, Int32, Uint32, Float32 };
struct ModbusRegister {
  std::string name;
  bool input_table = false;  // false: holding registers (FC 3), true: input registers (FC 4)
  int address = 0;
  RegisterType type = RegisterType::Uint16;
  bool word_swap = false;  // 32-bit values: low word first
  double scale = 1.0, offset = 0.0;
  int line = 0;  // where the mapping file defined it
  int words() const { return type == RegisterType::Int16 || type == RegisterType::Uint16 ? 1 : 2; }
};
struct ModbusConfig {
  std::string input;  // the --input name of a [modbus INPUT] table ("" for [modbus]): its values are
                      // "modbus.INPUT.NAME" instead of "modbus.NAME"
  double poll_s = 0.1;
  double response_timeout_s = 0.2;
  int unit_id = 1;
  std::string heartbeat;      // register name that must keep changing; empty = none
  int stale_after_polls = 5;  // heartbeat unchanged for this many polls = all signals invalid
  std::vector<ModbusRegister> registers;
  const ModbusRegister* find(std::string_view name) const;
  // The value key a register's readings are delivered under: "modbus.NAME" or "modbus.INPUT.NAME".
  std::string source_key(const ModbusRegister& r) const { return "modbus." + (input.empty() ? "" : input + ".") + r.name; }
};

// Decodes a Modbus register value from raw 16-bit words (big-endian words, as on the wire).
double modbus_register_value(const ModbusRegister& r, const std::uint16_t* words);

// The heartbeat register's history across polls (ModbusConfig::heartbeat).
struct ModbusHeartbeat {
  int same_polls = 0;  // consecutive polls the heartbeat words did not change
  bool seen = false;
  std::array<std::uint16_t, 2> last{0, 0};
};
// One register as a poll read it: its value, valid when finite.
struct ModbusReading {
  const ModbusRegister* reg = nullptr;
  double value = 0.0;
  bool valid = false;
};
// Interprets one complete poll: words[i] holds the words read for cfg.registers[i] (the second
// word unused by 16-bit types). Advances the heartbeat check; when the heartbeat has been stale
// for cfg.stale_after_polls polls, returns false and leaves `out` empty (every register is then
// invalid). Otherwise fills `out` with one reading per register, in the table's order.
bool interpret_modbus_poll(const ModbusConfig& cfg, std::span<const std::array<std::uint16_t, 2>> words,
                           ModbusHeartbeat& heartbeat, std::vector<ModbusReading>& out);

}  // namespace meter::controller
