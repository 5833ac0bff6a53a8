// Modbus register table lookups, the word -> value decoding of each register type and the
// interpretation of one poll's words (heartbeat staleness, finite values).
#include <algorithm>
#include <bit>
#include <cmath>

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

bool interpret_modbus_poll(const ModbusConfig& cfg, std::span<const std::array<std::uint16_t, 2>> words,
                           ModbusHeartbeat& hb, std::vector<ModbusReading>& out) {
  out.clear();
  const std::size_t n = std::min(words.size(), cfg.registers.size());
  if (!cfg.heartbeat.empty()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (cfg.registers[i].name != cfg.heartbeat) continue;
      const bool same = hb.seen && words[i] == hb.last;
      hb.same_polls = same ? hb.same_polls + 1 : 0;
      hb.last = words[i];
      hb.seen = true;
    }
    if (hb.same_polls >= cfg.stale_after_polls) return false;
  }
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = modbus_register_value(cfg.registers[i], words[i].data());
    out.push_back({&cfg.registers[i], v, std::isfinite(v)});
  }
  return true;
}

}  // namespace meter::controller
