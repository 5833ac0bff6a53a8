// A mapping's look-ups.
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller {

const OutputMapping* Mapping::find(protocol::SignalId id) const {
  for (auto& o : outputs)
    if (o.id == id) return &o;
  return nullptr;
}

const ModbusConfig* Mapping::modbus_table_of(std::string_view source) const {
  if (source.rfind("modbus.", 0) != 0) return nullptr;
  const std::string_view rest = source.substr(7);
  const auto dot = rest.find('.');
  if (dot == std::string_view::npos) return modbus && modbus->find(rest) ? &*modbus : nullptr;
  const auto it = modbus_inputs.find(rest.substr(0, dot));
  return it != modbus_inputs.end() && it->second.find(rest.substr(dot + 1)) ? &it->second : nullptr;
}

}  // namespace meter::controller
