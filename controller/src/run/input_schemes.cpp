// The --input schemes and what each one opens.
#include "meter/controller/run/input_schemes.hpp"

#include <array>
#include <stdexcept>

#include "meter/controller/input/log_channel.hpp"
#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/modbus_input.hpp"
#include "meter/controller/input/socketcan.hpp"
#include "open_input.hpp"

namespace meter::controller {
namespace {

std::unique_ptr<Input> open_socketcan(const LiveInputContext& c) {
  return std::make_unique<SocketCanInput>(c.address, can_filters(c.model.used_ids(c.index), c.db));
}

// The input's own table ([modbus NAME]) when the mapping has one, else the one [modbus] table
// (open_inputs has checked that several Modbus inputs each have their own).
std::unique_ptr<Input> open_modbus(const LiveInputContext& c, const char* transport) {
  if (const auto it = c.map.modbus_inputs.find(c.name); !c.name.empty() && it != c.map.modbus_inputs.end())
    return std::make_unique<ModbusInput>(transport + c.address, it->second);
  if (!c.map.modbus)
    throw std::runtime_error(c.map.file + ": the Modbus input " + (c.name.empty() ? "" : "'" + c.name + "' ") +
                             "needs its registers: [modbus.register NAME] sections" +
                             (c.name.empty() ? "" : ", or [modbus " + c.name + "] and [modbus.register " + c.name + ".NAME]"));
  return std::make_unique<ModbusInput>(transport + c.address, *c.map.modbus);
}
std::unique_ptr<Input> open_modbus_tcp(const LiveInputContext& c) { return open_modbus(c, "tcp:"); }
std::unique_ptr<Input> open_modbus_rtu(const LiveInputContext& c) { return open_modbus(c, "rtu:"); }

}  // namespace

std::span<const InputScheme> input_schemes() {
  // The registration: one entry per scheme.
  static const std::array schemes{
      InputScheme{"log", "log:FILE", "a recorded CAN log, FILE#N for its channel N alone", InputKind::Log, open_log_input, nullptr},
      InputScheme{"can", "can:IFACE", "SocketCAN, e.g. can:vcan0", InputKind::CanBus, nullptr, open_socketcan},
      InputScheme{"modbus-tcp", "modbus-tcp:HOST:PORT", "Modbus TCP", InputKind::Modbus, nullptr, open_modbus_tcp},
      InputScheme{"modbus-rtu", "modbus-rtu:DEV:BAUD[:8N1]", "Modbus RTU", InputKind::Modbus, nullptr, open_modbus_rtu},
  };
  return schemes;
}

std::string input_forms() {
  std::string forms;
  const auto schemes = input_schemes();
  for (std::size_t i = 0; i < schemes.size(); ++i)
    forms += (i == 0 ? "" : i + 1 == schemes.size() ? " or " : ", ") + std::string(schemes[i].form);
  return forms;
}

std::string input_forms_described() {
  std::string forms;
  for (const InputScheme& s : input_schemes()) {
    std::string what(s.what);
    if (s.kind == InputKind::Log) what += ": " + log_format_names();
    forms += (forms.empty() ? "" : ", ") + std::string(s.form) + " (" + what + ")";
  }
  return forms;
}

InputTarget parse_input_target(const std::string& target) {
  const auto colon = target.find(':');
  const std::string_view scheme = colon == std::string::npos ? std::string_view() : std::string_view(target).substr(0, colon);
  for (const InputScheme& s : input_schemes()) {
    if (s.scheme != scheme) continue;
    if (colon + 1 == target.size())
      throw std::invalid_argument("--input " + target + ": expected " + std::string(s.form) + ", with something after '" +
                                  std::string(s.scheme) + ":'");
    return InputTarget{&s, target.substr(colon + 1)};
  }
  throw std::invalid_argument("--input: expected [NAME=]" + input_forms() + ", got '" + target + "'" +
                              (scheme.empty() ? std::string(" (no scheme before a ':')")
                                              : " (unknown scheme '" + std::string(scheme) + "')"));
}

}  // namespace meter::controller
