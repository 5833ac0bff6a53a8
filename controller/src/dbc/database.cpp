// Database lookups: signals by name, messages by id (exact, then J1939 PGN) and by name; the
// names of the warning kinds.
#include "bit_layout.hpp"
#include "meter/controller/dbc/database.hpp"

namespace meter::controller {

using dbc_layout::motorola_msb_linear;

std::size_t DbcSignal::bytes_needed() const {
  if (little_endian) return (static_cast<std::size_t>(start_bit) + length - 1) / 8 + 1;
  return (static_cast<std::size_t>(motorola_msb_linear(start_bit)) + length - 1) / 8 + 1;
}

const std::string* DbcSignal::choice(std::int64_t raw) const {
  for (const auto& [v, t] : choices)
    if (v == raw) return &t;
  return nullptr;
}

int DbcMessage::find_signal(std::string_view n) const {
  for (std::size_t i = 0; i < signals.size(); ++i)
    if (signals[i].name == n) return static_cast<int>(i);
  return -1;
}

std::uint32_t j1939_pgn(std::uint32_t id29) {
  std::uint32_t pgn = (id29 >> 8) & 0x3FFFFu;
  if (((pgn >> 8) & 0xFFu) < 240) pgn &= 0x3FF00u;  // PDU1: PS is a destination address
  return pgn;
}

void Database::build_index() {
  by_id_.clear();
  by_pgn_.clear();
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const auto& m = messages[i];
    std::uint64_t key = m.id | (m.extended ? (1ull << 32) : 0);
    if (!by_id_.emplace(key, i).second)
      warnings.push_back({DbcWarningKind::Duplicate, m.line, "message " + m.name + ": id already used by " + messages[by_id_[key]].name + "; the first wins"});
    if (m.j1939) by_pgn_.emplace(j1939_pgn(m.id), i);
  }
}

const DbcMessage* Database::find(std::uint32_t id, bool extended) const {
  auto it = by_id_.find(id | (extended ? (1ull << 32) : 0));
  if (it != by_id_.end()) return &messages[it->second];
  if (extended && !by_pgn_.empty()) {
    auto p = by_pgn_.find(j1939_pgn(id));
    if (p != by_pgn_.end()) return &messages[p->second];
  }
  return nullptr;
}

std::string Database::skipped_note(std::string_view message, std::string_view signal) const {
  for (const auto& s : skipped)
    if (s.message == message && (s.signal == signal || s.signal.empty()))
      return "; its definition at " + file + ":" + std::to_string(s.line) + " was skipped: " + s.reason;
  return {};
}

const DbcMessage* Database::find(std::string_view name) const {
  for (const auto& m : messages)
    if (m.name == name) return &m;
  return nullptr;
}

const char* to_string(DbcWarningKind k) {
  switch (k) {
    case DbcWarningKind::MissingSemicolon: return "missing-semicolon";
    case DbcWarningKind::UnnamedComment: return "unnamed-comment";
    case DbcWarningKind::UnknownReference: return "unknown-reference";
    case DbcWarningKind::StandardIdAbove7FF: return "standard-id-above-7ff";
    case DbcWarningKind::Duplicate: return "duplicate";
    case DbcWarningKind::UnknownAttributeType: return "unknown-attribute-type";
    case DbcWarningKind::SignalOutsideMessage: return "signal-outside-message";
    case DbcWarningKind::SkippedStatement: return "skipped-statement";
    case DbcWarningKind::ReservedIdBits: return "reserved-id-bits";
    case DbcWarningKind::NotUtf8: return "not-utf8";
  }
  return "?";
}

}  // namespace meter::controller
