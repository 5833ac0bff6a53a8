// Resolution of the recorded references once every message is known: comments, value tables,
// value types and extended multiplexing onto their signals (unknown references become warnings),
// simple multiplexing onto the message's 'M' switch, layout checks against the message size, and
// the attributes (GenMsgCycleTime, VFrameFormat incl. CAN FD and J1939PG, ProtocolType J1939).
#include <algorithm>
#include <limits>
#include <set>

#include "parser.hpp"

namespace meter::controller::dbc_parse {

namespace {
std::uint64_t id_key(std::uint32_t id, bool extended) { return id | (extended ? (1ull << 32) : 0); }
}  // namespace

// The first message (file order) with the id and frame format; a reference without the extended
// flag to an id above 0x7FF may also mean the extended message of that id.
DbcMessage* DbcParser::message_by_raw(std::uint32_t raw) {
  bool ext = (raw & 0x80000000u) != 0;
  std::uint32_t id = raw & 0x1FFFFFFFu;
  std::size_t first = db_.messages.size();
  auto consider = [&](bool extended) {
    if (auto it = first_by_id_.find(id_key(id, extended)); it != first_by_id_.end()) first = std::min(first, it->second);
  };
  consider(ext);
  if (!ext && id > 0x7FF) consider(true);
  return first < db_.messages.size() ? &db_.messages[first] : nullptr;
}

std::optional<std::string> DbcParser::enum_text(const std::string& name, const AttrValue& v) {
  if (v.is_string) return v.text;
  auto it = enum_defs_.find(name);
  if (it == enum_defs_.end()) return std::nullopt;
  // Checked as a double first: converting one outside size_t's range (negative, huge, NaN) is
  // undefined behaviour.
  if (!(v.number >= 0.0 && v.number < double(it->second.size()))) return std::nullopt;
  return it->second[static_cast<std::size_t>(v.number)];
}

void DbcParser::finish() {
  for (std::size_t i = 0; i < db_.messages.size(); ++i)
    first_by_id_.try_emplace(id_key(db_.messages[i].id, db_.messages[i].extended), i);
  apply_signal_statements();
  resolve_plain_multiplexing();
  apply_attributes();
}

void DbcParser::apply_signal_statements() {
  std::set<std::pair<const DbcSignal*, char>> seen;  // a second VAL_ / SIG_VALTYPE_ for a signal
  for (auto& p : pending_) {
    DbcMessage* m = message_by_raw(p.raw_id);
    if (!m) {
      if (!independent(p.raw_id))
        warn(DbcWarningKind::UnknownReference, p.line, "reference to unknown message id " + std::to_string(p.raw_id) + " ignored");
      continue;
    }
    if (p.kind == 'c') {
      m->comment = p.comment;
      continue;
    }
    int si = m->find_signal(p.signal);
    if (si < 0) {
      warn(DbcWarningKind::UnknownReference, p.line, "reference to unknown signal " + m->name + "." + p.signal + " ignored");
      continue;
    }
    DbcSignal& s = m->signals[static_cast<std::size_t>(si)];
    if ((p.kind == 'V' || p.kind == 'T' || p.kind == 'M') && !seen.insert({&s, p.kind}).second)
      warn(DbcWarningKind::Duplicate, p.line, std::string(p.kind == 'V' ? "VAL_" : p.kind == 'T' ? "SIG_VALTYPE_" : "SG_MUL_VAL_") +
                                                  " for " + m->name + "." + s.name + " given again: the last wins");
    switch (p.kind) {
      case 'C': s.comment = p.comment; break;
      case 'V': s.choices = p.choices; break;
      case 'T':
        if ((p.valtype == 1 && s.length != 32) || (p.valtype == 2 && s.length != 64)) {
          warn(DbcWarningKind::SkippedStatement, p.line,
               "SIG_VALTYPE_ skipped: " + m->name + "." + s.name + ": IEEE " + (p.valtype == 1 ? "float needs a 32" : "double needs a 64") +
                   "-bit signal, it has " + std::to_string(s.length) + " bits; decoded as an integer");
          break;
        }
        s.value_type = p.valtype == 1 ? ValueType::Float32 : p.valtype == 2 ? ValueType::Float64 : ValueType::Integer;
        break;
      case 'M': {
        int sw = m->find_signal(p.switch_name);
        if (sw < 0 || !m->signals[static_cast<std::size_t>(sw)].is_multiplexor) {
          warn(DbcWarningKind::SkippedStatement, p.line,
               "SG_MUL_VAL_ skipped: " + m->name + "." + s.name + ": expected a multiplexor signal, '" + p.switch_name + "' is not one");
          break;
        }
        s.mux_switch = sw;
        s.mux_ranges = p.ranges;
        break;
      }
      default: break;
    }
  }
}

void DbcParser::resolve_plain_multiplexing() {
  for (auto& m : db_.messages) {
    int plain = -1;
    for (std::size_t i = 0; i < m.signals.size(); ++i)
      if (m.signals[i].is_multiplexor && m.signals[i].mux_ranges.empty()) plain = static_cast<int>(i);
    for (std::size_t i = 0; i < m.signals.size();) {
      auto& s = m.signals[i];
      if (s.mux_switch == -2 && plain < 0) {
        std::string why = "multiplexed (m<N>) but the message has no multiplexor 'M' signal";
        warn(DbcWarningKind::SkippedStatement, s.line, "SG_ skipped: signal " + m.name + "." + s.name + " is " + why);
        db_.skipped.push_back({m.name, s.name, s.line, "it is " + why});
        m.signals.erase(m.signals.begin() + static_cast<std::ptrdiff_t>(i));
        for (auto& other : m.signals)  // switches named by index move down with the erase
          if (other.mux_switch > static_cast<int>(i)) --other.mux_switch;
        continue;
      }
      if (s.mux_switch == -2) s.mux_switch = plain;
      ++i;
    }
    for (std::size_t i = 0; i < m.signals.size(); ++i) {
      const auto& s = m.signals[i];
      if (s.bytes_needed() > m.size)
        warn(DbcWarningKind::SignalOutsideMessage, s.line,
             "signal " + m.name + "." + s.name + " reaches byte " + std::to_string(s.bytes_needed()) + " of a " +
                 std::to_string(m.size) + "-byte message");
    }
  }
}

void DbcParser::apply_attributes() {
  // A cycle time is a whole number of ms an int holds: a larger one (or a NaN) is no cycle time.
  auto cycle_time_fits = [](double ms) { return ms <= double(std::numeric_limits<int>::max()); };
  auto apply_msg_attr = [&](DbcMessage& m, const std::string& name, const AttrValue& v) {
    if (name == "GenMsgCycleTime" && !v.is_string) {
      if (v.number > 0 && cycle_time_fits(v.number)) m.cycle_time_ms = static_cast<int>(v.number);
      else m.cycle_time_ms.reset();
    } else if (name == "VFrameFormat") {
      auto t = enum_text(name, v);
      if (t) {
        m.j1939 = *t == "J1939PG";
        m.fd = t->find("CAN_FD") != std::string::npos;
      }
    }
  };
  for (auto& a : attrs_)
    if (a.object == 'G' && a.name == "ProtocolType" && a.value.is_string) db_.protocol_type = a.value.text;
  // Named once, where it is written: a cycle time too large for any message.
  auto check_cycle_time = [&](const std::string& name, const AttrValue& v, int line, const std::string& what) {
    if (name == "GenMsgCycleTime" && !v.is_string && v.number > 0 && !cycle_time_fits(v.number))
      warn(DbcWarningKind::SkippedStatement, line,
           what + " \"GenMsgCycleTime\" " + std::to_string(v.number) + " ms: expected a cycle time of at most " +
               std::to_string(std::numeric_limits<int>::max()) + " ms; ignored (no cycle time)");
  };
  for (auto& [name, v] : attr_defaults_) check_cycle_time(name, v, attr_default_lines_[name], "BA_DEF_DEF_");
  for (auto& a : attrs_)
    if (a.object == 'B') check_cycle_time(a.name, a.value, a.line, "BA_");
  for (auto& m : db_.messages) {
    for (auto& [name, v] : attr_defaults_) apply_msg_attr(m, name, v);
    if (db_.protocol_type == "J1939") m.j1939 = true;
    if (!m.extended) m.j1939 = false;
  }
  for (auto& a : attrs_) {
    if (a.object != 'B' && a.object != 'S') continue;
    DbcMessage* m = message_by_raw(a.raw_id);
    if (!m) {
      if (!independent(a.raw_id))
        warn(DbcWarningKind::UnknownReference, a.line, "BA_ \"" + a.name + "\" for unknown message id " + std::to_string(a.raw_id) + " ignored");
      continue;
    }
    if (a.object == 'S') {  // signal attributes: none that meter uses, but a wrong name is a quirk
      if (m->find_signal(a.signal) < 0)
        warn(DbcWarningKind::UnknownReference, a.line, "BA_ \"" + a.name + "\" for unknown signal " + m->name + "." + a.signal + " ignored");
      continue;
    }
    apply_msg_attr(*m, a.name, a.value);
    if (!m->extended) m->j1939 = false;
  }
}

}  // namespace meter::controller::dbc_parse
