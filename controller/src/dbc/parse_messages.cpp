// BO_ message and SG_ signal lines: ids (extended bit 31), sizes up to 64 bytes, multiplexer
// indicators (M, mN, mNM), bit layout, factor/offset, range, unit and receivers.
#include "parser.hpp"

namespace meter::controller::dbc_parse {

void DbcParser::parse_message(int kw_line) {
  std::uint64_t raw = lex_.uint_lit("message id");
  if (raw > 0xFFFFFFFFull) lex_.error("message id does not fit 32 bits");
  std::string name = lex_.need_ident("a message name");
  defining_name_ = name;
  lex_.expect(':');
  std::uint64_t size = lex_.uint_lit("message size");
  if (size > 64) lex_.error("message size " + std::to_string(size) + " is above 64 bytes");
  lex_.skip_inline_ws();
  std::string tx = lex_.eol() ? std::string() : lex_.ident();
  defining_name_.clear();
  skipped_message_.clear();
  // The pseudo message of signals without a frame, by its id or (some tools write other ids) its name.
  if (raw == kIndependentSignalsId || name == "VECTOR__INDEPENDENT_SIG_MSG") {
    // Signals without a message: no frame ever carries them.
    independent_raw_ = static_cast<std::uint32_t>(raw);
    current_ = -1;
    current_skipped_ = true;
    return;
  }
  DbcMessage m;
  if (raw & 0x60000000u)
    warn(DbcWarningKind::ReservedIdBits, kw_line,
         "message " + name + ": id " + std::to_string(raw) + " sets bit 29 or 30, which no CAN id has; ignored");
  m.extended = (raw & 0x80000000u) != 0;
  m.id = static_cast<std::uint32_t>(raw & 0x1FFFFFFFu);
  if (!m.extended && m.id > 0x7FF) {
    warn(DbcWarningKind::StandardIdAbove7FF, kw_line,
         "message " + name + ": standard id " + std::to_string(m.id) + " above 0x7FF; treated as extended");
    m.extended = true;
  }
  m.name = name;
  m.size = static_cast<std::uint8_t>(size);
  m.transmitter = tx;
  m.line = kw_line;
  db_.messages.push_back(std::move(m));
  current_ = static_cast<std::ptrdiff_t>(db_.messages.size()) - 1;
  current_skipped_ = false;
}

void DbcParser::parse_signal(int kw_line) {
  DbcSignal sig;
  sig.line = kw_line;
  sig.name = lex_.need_ident("a signal name");
  defining_name_ = sig.name;
  lex_.skip_ws();
  int mux_value = -1;
  if (lex_.peek() != ':') {
    std::string m = lex_.ident();
    if (m == "M") {
      sig.is_multiplexor = true;
    } else if (m.size() >= 2 && m[0] == 'm') {
      std::size_t i = 1;
      std::uint64_t v = 0;
      while (i < m.size() && m[i] >= '0' && m[i] <= '9') v = v * 10 + static_cast<unsigned>(m[i++] - '0');
      if (i == 1 || (i < m.size() && !(m[i] == 'M' && i + 1 == m.size())))
        lex_.error("signal " + sig.name + ": expected multiplexer indicator 'M', 'm<N>' or 'm<N>M' but found '" + m + "'");
      if (i < m.size()) sig.is_multiplexor = true;
      mux_value = static_cast<int>(v);
      sig.mux_ranges.push_back({v, v});
    } else {
      lex_.error("signal " + sig.name + ": expected ':' or a multiplexer indicator but found '" + m + "'");
    }
  }
  lex_.expect(':');
  std::uint64_t start = lex_.uint_lit("start bit");
  lex_.expect('|');
  std::uint64_t len = lex_.uint_lit("signal length");
  lex_.expect('@');
  char order = lex_.peek();
  if (order != '0' && order != '1') lex_.error("signal " + sig.name + ": expected byte order '@0' (Motorola) or '@1' (Intel)");
  lex_.advance();
  char sign = lex_.peek();
  if (sign != '+' && sign != '-') lex_.error("signal " + sig.name + ": expected '+' (unsigned) or '-' (signed) after the byte order");
  lex_.advance();
  lex_.expect('(');
  sig.factor = lex_.number("factor");
  lex_.expect(',');
  sig.offset = lex_.number("offset");
  lex_.expect(')');
  lex_.expect('[');
  sig.minimum = lex_.number("minimum");
  lex_.expect('|');
  sig.maximum = lex_.number("maximum");
  lex_.expect(']');
  sig.unit = lex_.string_lit();
  lex_.skip_inline_ws();
  while (!lex_.eol()) {
    if (lex_.peek() == ',') {
      lex_.advance();
      lex_.skip_inline_ws();
      continue;
    }
    std::string r = lex_.ident();
    if (r.empty()) lex_.error("signal " + sig.name + ": expected receiver node names but found '" + lex_.preview() + "'");
    sig.receivers.push_back(r);
    lex_.skip_inline_ws();
  }
  if (len == 0 || len > 64) lex_.error("signal " + sig.name + ": length " + std::to_string(len) + " is outside 1..64");
  if (start >= 512) lex_.error("signal " + sig.name + ": start bit " + std::to_string(start) + " is beyond 64 bytes");
  if (sig.factor == 0.0) lex_.error("signal " + sig.name + ": factor 0 would lose every value");
  sig.start_bit = static_cast<std::uint16_t>(start);
  sig.length = static_cast<std::uint16_t>(len);
  sig.little_endian = order == '1';
  sig.is_signed = sign == '-';
  if (current_ < 0 && !current_skipped_) lex_.error("SG_ " + sig.name + " before any BO_ (a signal must follow its message)");
  defining_name_.clear();
  if (current_skipped_) {
    if (!skipped_message_.empty())
      db_.skipped.push_back({skipped_message_, sig.name, kw_line,
                             "its message's BO_ at line " + std::to_string(skipped_message_line_) + " was skipped"});
    return;
  }
  DbcMessage& cur = db_.messages[static_cast<std::size_t>(current_)];
  if (cur.find_signal(sig.name) >= 0) {
    warn(DbcWarningKind::Duplicate, kw_line, "message " + cur.name + ": duplicate signal " + sig.name + " ignored (the first wins)");
    return;
  }
  if (mux_value >= 0) sig.mux_switch = -2;  // resolved in finish()
  cur.signals.push_back(std::move(sig));
}

}  // namespace meter::controller::dbc_parse
