// Modbus register table lookups and the word -> value decoding of each register type.
#include <bit>

#include "meter/controller/input/modbus_registers.hpp"

namespace meter::controller {

const ModbusRegister* ModbusConfig::find(std::string_view name) const {
  for (auto& r : registers)
    if (r.name == name) return &r;
  return nullptr;
}

double modbus_register_value(const ModbusRegister& r, const std::uint16_t* w) {
  // 16-bit types own one word only: the second is read for 32-bit types alone.
  std::uint32_t v32 = 0;
  if (r.words() == 2)
    v32 = r.word_swap ? (static_cast<std::uint32_t>(w[1]) << 16) | w[0] : (static_cast<std::uint32_t>(w[0]) << 16) | w[1];
  double v = 0;
  switch (r.type) {
    case RegisterType::Int16: v = static_cast<std::int16_t>(w[0]); break;
    case RegisterType::Uint16: v = w[0]; break;
    case RegisterType::Int32: v = static_cast<std::int32_t>(v32); break;
    case RegisterType::Uint32: v = v32; break;
    case RegisterType::Float32: v = std::bit_cast<float>(v32); break;
  }
  return v * r.scale + r.offset;
}

}  // namespace meter::controller
