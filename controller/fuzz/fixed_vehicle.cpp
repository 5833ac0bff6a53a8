#include "fixed_vehicle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <span>
#include <string>
#include <vector>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/model/model.hpp"

namespace meter::controller::fuzz {

const Database& demo_dbc() {
  static const Database db = load_dbc(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.dbc");
  return db;
}

const Mapping& demo_mapping() {
  static const Mapping map = load_mapping(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.map");
  return map;
}

void drive_demo_vehicle(const ParsedLog& log) {
  // Every frame and bad record is a record of its own (a binary file's header, record 0, aside).
  const auto bad = std::count_if(log.bad_lines.begin(), log.bad_lines.end(), [](const BadLine& b) { return b.line > 0; });
  if (log.frames.size() + static_cast<std::size_t>(bad) > log.lines) std::abort();
  const Database& db = demo_dbc();
  Model model(&db, demo_mapping());
  std::vector<DecodedSignal> decoded;
  bool started = false;
  for (const CanFrame& f : log.frames) {
    if (f.len > (f.fd ? 64 : 8) && !f.rtr) std::abort();
    if (!started) model.start(f.timestamp_ns), started = true;
    model.on_frame(f);
    model.update(f.timestamp_ns);
    if (!f.error && !f.rtr)
      if (const DbcMessage* m = db.find(f.id, f.extended))
        decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), decoded);
  }
}

bool same_logged_frame(const CanFrame& a, const CanFrame& b, bool with_class) {
  if (a.error || b.error) return a.error == b.error && a.channel == b.channel && (!with_class || (a.id == b.id && a.len == b.len &&
                                                                                                 std::memcmp(a.data.data(), b.data.data(), a.len) == 0));
  return a.id == b.id && a.extended == b.extended && a.rtr == b.rtr && a.fd == b.fd && a.fd_flags == b.fd_flags &&
         a.len == b.len && a.len8_dlc == b.len8_dlc && a.channel == b.channel &&
         std::memcmp(a.data.data(), b.data.data(), a.rtr ? 0 : a.len) == 0;
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
