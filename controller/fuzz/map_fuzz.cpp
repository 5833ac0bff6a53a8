// Fuzzes the map-file parser the way meter-controller uses a mapping: parse the text, build the
// model against the demo vehicle's DBC (which resolves every "Message.Signal" source), then run it
// for a second of frames carrying the input's bytes and register values for every Modbus source.
// Every rejection must be an exception naming the file and line ("fuzz.map:N: ...").
#include <algorithm>
#include <cstdlib>
#include <optional>

#include "fixed_vehicle.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "meter/controller/model/model.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Database& db = fuzz::demo_dbc();
  std::optional<Model> model;
  if (!fuzz::model_for_map(model, db, fuzz::as_text(data, size))) return 0;
  model->start(0);
  const std::string_view bytes = fuzz::as_text(data, size);
  for (std::int64_t tick = 0; tick < 100; ++tick) {
    const CanFrame f = fuzz::fuzz_frame(db, tick, bytes, 31);
    model->on_frame(f);
    if (const auto& mb = model->mapping().modbus)
      for (const ModbusRegister& r : mb->registers) model->on_value(mb->source_key(r), static_cast<double>(tick), true, f.timestamp_ns);
    for (const auto& [input, table] : model->mapping().modbus_inputs)
      for (const ModbusRegister& r : table.registers) model->on_value(table.source_key(r), static_cast<double>(tick), true, f.timestamp_ns);
    model->update(f.timestamp_ns);
    fuzz::require_finite_outputs(*model);  // never a silent NaN on the link
  }
  return 0;
}
