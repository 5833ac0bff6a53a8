// check-dbc: a DBC's summary (messages, signal kinds, cycle times), the lint report (counts, the
// tolerated problems by kind) and each problem with its file:line. --strict refuses any problem.
#include <cstdio>
#include <ostream>

#include "command_output.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/run/check_dbc_command.hpp"

namespace meter::controller {

int check_dbc_command(const std::string& dbc_path, std::ostream& out, std::ostream& err, bool strict) {
  Database db;
  if (!load_dbc_reporting(dbc_path, db, err)) return 1;
  std::size_t muxed_messages = 0;
  for (const auto& m : db.messages) {
    bool muxed = false;
    for (const auto& s : m.signals) muxed |= s.is_multiplexor;
    muxed_messages += muxed;
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
  std::size_t by_kind[kDbcWarningKinds] = {};
  for (const auto& w : db.warnings) ++by_kind[static_cast<int>(w.kind)];
  out << "lint: " << db.messages.size() << " message(s), " << signals << " signal(s), " << muxed_messages
      << " multiplexed message(s), " << db.warnings.size() << " warning(s)" << (strict && !db.warnings.empty() ? " refused by --strict" : "")
      << "\n";
  for (int k = 0; k < kDbcWarningKinds; ++k)
    if (by_kind[k]) out << "  " << to_string(static_cast<DbcWarningKind>(k)) << ": " << by_kind[k] << "\n";
  std::ostream& list = strict ? err : out;
  const char* level = strict ? "error" : "warning";
  for (const auto& w : db.warnings)
    list << dbc_path << ":" << w.line << ": " << level << " [" << to_string(w.kind) << "]: " << w.text << "\n";
  return strict && !db.warnings.empty() ? 1 : 0;
}

}  // namespace meter::controller
