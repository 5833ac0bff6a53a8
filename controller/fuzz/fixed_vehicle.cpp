#include "fixed_vehicle.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

namespace meter::controller::fuzz {

const Database& demo_dbc() {
  static const Database db = load_dbc(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.dbc");
  return db;
}

const Mapping& demo_mapping() {
  static const Mapping map = load_mapping(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.map");
  return map;
}

bool model_for_map(std::optional<Model>& model, const Database& db, std::string_view map_text) {
  try {
    model.emplace(&db, parse_mapping(map_text, "fuzz.map"));
    return true;
  } catch (const std::exception& e) {
    if (!std::strstr(e.what(), "fuzz.map:")) std::abort();  // an error that does not say where
    return false;
  }
}

CanFrame fuzz_frame(const Database& db, std::int64_t tick, std::string_view bytes, std::size_t stride, int short_every) {
  const DbcMessage& m = db.messages[static_cast<std::size_t>(tick) % db.messages.size()];
  CanFrame f;
  f.id = m.id, f.extended = m.extended, f.timestamp_ns = tick * 10'000'000;
  f.len = static_cast<std::uint8_t>(m.size - (short_every > 0 && tick % short_every == short_every / 2 && m.size > 0));
  for (std::size_t i = 0; i < f.len; ++i)
    f.data[i] = bytes.empty() ? 0 : static_cast<std::uint8_t>(bytes[(static_cast<std::size_t>(tick) * stride + i) % bytes.size()]);
  return f;
}

void require_finite_outputs(const Model& model) {
  for (const ModelOutput& o : model.outputs())
    if (!std::isfinite(o.value)) std::abort();
}

}  // namespace meter::controller::fuzz
