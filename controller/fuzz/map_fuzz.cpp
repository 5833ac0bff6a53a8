// Fuzzes the map-file parser the way meter-controller uses a mapping: parse the text, build the
// model against the demo vehicle's DBC (which resolves every "Message.Signal" source), then run it
// for a second of frames carrying the input's bytes and register values for every Modbus source.
// Every rejection must be an exception naming the file and line ("fuzz.map:N: ...").
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>

#include "fixed_vehicle.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "meter/controller/model/model.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Database& db = fuzz::demo_dbc();
  std::optional<Model> model;
  try {
    model.emplace(&db, parse_mapping(fuzz::as_text(data, size), "fuzz.map"));
  } catch (const std::exception& e) {
    if (!std::strstr(e.what(), "fuzz.map:")) std::abort();  // an error that does not say where
    return 0;
  }
  model->start(0);
  CanFrame f;
  for (std::int64_t tick = 0; tick < 100; ++tick) {
    const std::int64_t t = tick * 10'000'000;
    const DbcMessage& m = db.messages[static_cast<std::size_t>(tick) % db.messages.size()];
    f.id = m.id, f.extended = m.extended, f.len = m.size, f.timestamp_ns = t;
    for (std::size_t i = 0; i < f.len; ++i) f.data[i] = size ? data[(static_cast<std::size_t>(tick) * 31 + i) % size] : 0;
    model->on_frame(f);
    if (const auto& mb = model->mapping().modbus)
      for (const ModbusRegister& r : mb->registers) model->on_value(mb->source_key(r), static_cast<double>(tick), true, t);
    for (const auto& [input, table] : model->mapping().modbus_inputs)
      for (const ModbusRegister& r : table.registers) model->on_value(table.source_key(r), static_cast<double>(tick), true, t);
    model->update(t);
    for (const ModelOutput& o : model->outputs())
      if (!std::isfinite(o.value)) std::abort();  // never a silent NaN on the link
  }
  return 0;
}
