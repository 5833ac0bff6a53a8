// check-dbc: a DBC's summary (messages, signal kinds, cycle times) and the problems the parser tolerated.
#include <cstdio>
#include <ostream>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/run/commands.hpp"

namespace meter::controller {

int check_dbc_command(const std::string& dbc_path, std::ostream& out, std::ostream& err) {
  Database db;
  try {
    db = load_dbc(dbc_path);
  } catch (const DbcError& e) {
    err << e.what() << "\n";
    return 1;
  }
  std::size_t signals = 0, mux = 0, floats = 0, with_cycle = 0, j1939 = 0, ext = 0, motorola = 0, intel = 0, tables = 0;
  for (const auto& m : db.messages) {
    signals += m.signals.size();
    with_cycle += m.cycle_time_ms.has_value();
    j1939 += m.j1939;
    ext += m.extended;
    for (const auto& s : m.signals) {
      mux += s.is_multiplexor || s.mux_switch >= 0;
      floats += s.value_type != ValueType::Integer;
      (s.little_endian ? intel : motorola)++;
      tables += !s.choices.empty();
    }
  }
  out << dbc_path << ": DBC version \"" << db.version << "\", " << db.nodes.size() << " node(s), " << db.messages.size()
      << " message(s), " << signals << " signal(s)\n";
  out << "  extended ids: " << ext << ", J1939 (PGN matched): " << j1939 << ", with GenMsgCycleTime: " << with_cycle
      << "\n  signals: " << intel << " Intel, " << motorola << " Motorola, " << mux << " multiplexing, " << floats
      << " IEEE float, " << tables << " with value tables\n";
  for (const auto& m : db.messages) {
    char id[24];
    std::snprintf(id, sizeof id, m.extended ? "0x%08X" : "0x%03X", m.id);
    out << "  " << id << " " << m.name << " " << int(m.size) << " bytes, "
        << (m.cycle_time_ms ? std::to_string(*m.cycle_time_ms) + " ms" : std::string("no cycle time")) << ", "
        << m.signals.size() << " signal(s)\n";
  }
  if (db.warnings.empty()) {
    out << "  no problems found\n";
  } else {
    out << "  " << db.warnings.size() << " problem(s):\n";
    for (const auto& w : db.warnings) out << "    " << dbc_path << ":" << w.line << ": " << w.text << "\n";
  }
  return 0;
}

}  // namespace meter::controller
