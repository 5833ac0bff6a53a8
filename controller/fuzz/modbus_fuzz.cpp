// Fuzzes the Modbus response handling: the register words a poll returns, interpreted as the
// Modbus input does (interpret_modbus_poll: word order, type, scale, the heartbeat check) and
// handed to a model mapping every register to a catalog signal. The input is a run of polls, each
// two 16-bit words per register of a fixed table holding every register type and word order. A
// reading is valid exactly when its value is finite, and no output may carry a non-finite value.
#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "fixed_vehicle.hpp"
#include "meter/controller/input/modbus_registers.hpp"
#include "meter/controller/model/model.hpp"

using namespace meter::controller;

namespace {
constexpr const char* kMapping = R"(
[modbus]
poll = 100ms
heartbeat = hb
stale_after = 3

[modbus.register hb]
address = 0
type = uint16

[modbus.register speed]
address = 1
type = float32
word_order = low_first
scale = 3.6

[modbus.register rpm]
table = input
address = 3
type = uint32

[modbus.register temp]
address = 5
type = int16
scale = 0.1
offset = -40

[modbus.register fuel]
address = 6
type = float32

[modbus.register gear]
address = 8
type = int32
word_order = low_first

[Vehicle.Speed]
source = modbus.speed
needle = 0.15
timeout = 1s

[Vehicle.Powertrain.CombustionEngine.Speed]
source = modbus.rpm
timeout = 1s

[Vehicle.Powertrain.CombustionEngine.ECT]
source = modbus.temp
timeout = 1s

[Vehicle.Powertrain.FuelSystem.RelativeLevel]
source = modbus.fuel
fuel = true
timeout = 1s

[Vehicle.Powertrain.Transmission.CurrentGear]
source = modbus.gear
timeout = 1s
)";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Mapping mapping = parse_mapping(kMapping, "modbus-fuzz.map");
  const ModbusConfig& cfg = *mapping.modbus;
  Model model(nullptr, mapping);
  model.start(0);
  ModbusHeartbeat heartbeat;
  std::vector<std::array<std::uint16_t, 2>> words(cfg.registers.size());
  std::vector<ModbusReading> readings;
  const std::size_t poll_bytes = cfg.registers.size() * 4;
  std::int64_t t = 0;
  for (std::size_t at = 0; at + poll_bytes <= size; at += poll_bytes) {
    for (std::size_t i = 0; i < words.size(); ++i) {
      const std::uint8_t* w = data + at + i * 4;
      words[i] = {static_cast<std::uint16_t>(w[0] << 8 | w[1]), static_cast<std::uint16_t>(w[2] << 8 | w[3])};
    }
    t += 100'000'000;
    if (interpret_modbus_poll(cfg, words, heartbeat, readings)) {
      if (readings.size() != cfg.registers.size()) std::abort();
      for (const ModbusReading& r : readings) {
        if (r.valid != std::isfinite(r.value)) std::abort();
        model.on_value("modbus." + r.reg->name, r.value, r.valid, t);
      }
    } else {
      if (!readings.empty() || heartbeat.same_polls < cfg.stale_after_polls) std::abort();
      for (const ModbusRegister& r : cfg.registers) model.on_value("modbus." + r.name, 0.0, false, t);
    }
    model.update(t);
    for (const ModelOutput& o : model.outputs())
      if (!std::isfinite(o.value)) std::abort();
  }
  return 0;
}
