// dump-dbc: the parsed database as one JSON document, every field of every message and signal
// (doubles round-trip exactly), so other tools and parsers can be compared with meter's reading.
#include <nlohmann/json.hpp>
#include <ostream>

#include "command_output.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/run/dump_dbc_command.hpp"

namespace meter::controller {
namespace {

const char* value_type_name(ValueType t) {
  switch (t) {
    case ValueType::Float32: return "float32";
    case ValueType::Float64: return "float64";
    case ValueType::Integer: break;
  }
  return "integer";
}

nlohmann::json signal_json(const DbcMessage& m, const DbcSignal& s) {
  nlohmann::json j = {{"name", s.name},
                      {"start_bit", s.start_bit},
                      {"length", s.length},
                      {"little_endian", s.little_endian},
                      {"signed", s.is_signed},
                      {"value_type", value_type_name(s.value_type)},
                      {"factor", s.factor},
                      {"offset", s.offset},
                      {"minimum", s.minimum},
                      {"maximum", s.maximum},
                      {"unit", s.unit},
                      {"multiplexor", s.is_multiplexor},
                      {"line", s.line}};
  if (s.mux_switch >= 0) {
    j["mux_switch"] = m.signals[static_cast<std::size_t>(s.mux_switch)].name;
    nlohmann::json ranges = nlohmann::json::array();
    for (const auto& r : s.mux_ranges) ranges.push_back({r.lo, r.hi});
    j["mux_ranges"] = ranges;
  }
  nlohmann::json choices = nlohmann::json::array();
  for (const auto& [v, t] : s.choices) choices.push_back({v, t});
  j["choices"] = choices;
  return j;
}

}  // namespace

int dump_dbc_command(const std::string& dbc_path, std::ostream& out, std::ostream& err) {
  Database db;
  if (!load_dbc_reporting(dbc_path, db, err)) return 1;
  nlohmann::json messages = nlohmann::json::array();
  for (const auto& m : db.messages) {
    nlohmann::json signals = nlohmann::json::array();
    for (const auto& s : m.signals) signals.push_back(signal_json(m, s));
    messages.push_back({{"id", m.id},
                        {"extended", m.extended},
                        {"name", m.name},
                        {"size", m.size},
                        {"cycle_time_ms", m.cycle_time_ms ? nlohmann::json(*m.cycle_time_ms) : nlohmann::json()},
                        {"fd", m.fd},
                        {"j1939", m.j1939},
                        {"line", m.line},
                        {"signals", signals}});
  }
  nlohmann::json warnings = nlohmann::json::array();
  for (const auto& w : db.warnings) warnings.push_back({{"kind", to_string(w.kind)}, {"line", w.line}, {"text", w.text}});
  nlohmann::json doc = {{"file", dbc_path}, {"version", db.version}, {"nodes", db.nodes}, {"messages", messages}, {"warnings", warnings}};
  // Replacement characters for invalid UTF-8 (after cp1252 conversion there is none): never a throw.
  out << doc.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  return 0;
}

}  // namespace meter::controller
