// DBC parser. Written against the file grammar (Vector's DBC format description) and the quirks
// of real files: "SG_ X:" without a space, "(0.1, 0)" with spaces, // comments, CRLF, cp1252 text,
// the VECTOR__INDEPENDENT_SIG_MSG pseudo message, and sections it does not need (skipped by ';').
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "meter/controller/dbc.hpp"

namespace meter::controller {
namespace {

constexpr std::uint32_t kIndependentSignalsId = 0xC0000000u;  // VECTOR__INDEPENDENT_SIG_MSG

bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t n = (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : 0;
    if (n == 0 || i + n >= s.size()) return false;
    for (std::size_t k = 1; k <= n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return false;
    i += n + 1;
  }
  return true;
}

// Windows-1252 to UTF-8 (0x80..0x9F differ from Latin-1; undefined bytes become U+FFFD).
std::string cp1252_to_utf8(std::string_view s) {
  static constexpr char16_t k80[32] = {
      0x20AC, 0xFFFD, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160,
      0x2039, 0x0152, 0xFFFD, 0x017D, 0xFFFD, 0xFFFD, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022,
      0x2013, 0x2014, 0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0xFFFD, 0x017E, 0x0178};
  std::string out;
  out.reserve(s.size() + s.size() / 8);
  for (unsigned char c : s) {
    char32_t cp = c < 0x80 ? c : c < 0xA0 ? k80[c - 0x80] : c;
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }
  return out;
}

struct AttrValue {
  bool is_string = false;
  double number = 0;
  std::string text;
};

struct PendingAttr {
  int line;
  std::string name;
  char object;  // 'G' global, 'B' message, 'S' signal, 'N' node, 'E' env
  std::uint32_t raw_id = 0;
  std::string signal;
  AttrValue value;
};

class Parser {
 public:
  Parser(std::string_view text, std::string file) : s_(text), file_(std::move(file)) {}

  Database run() {
    db_.file = file_;
    for (;;) {
      skip_ws();
      if (eof()) break;
      int kw_line = line_;
      std::string kw = ident();
      if (kw.empty()) error("expected a keyword (BO_, SG_, CM_, BA_, VAL_, ...) but found '" + preview() + "'");
      if (kw == "VERSION") {
        skip_ws();
        db_.version = string_lit();
      } else if (kw == "NS_") {
        expect(':');
        // The NS_ list is indented; it ends at the first token that starts a line.
        for (;;) {
          skip_ws();
          if (eof() || pos_ == line_start_) break;
          if (ident().empty()) error("NS_: expected a keyword name");
        }
      } else if (kw == "BS_") {
        expect(':');
        skip_line();
      } else if (kw == "BU_") {
        expect(':');
        while (skip_inline_ws(), !eol()) {
          std::string n = ident();
          if (n.empty()) error("BU_: expected a node name");
          db_.nodes.push_back(n);
        }
      } else if (kw == "BO_") {
        parse_message(kw_line);
      } else if (kw == "SG_") {
        parse_signal(kw_line);
      } else if (kw == "CM_") {
        parse_comment();
      } else if (kw == "BA_DEF_") {
        parse_attr_def();
      } else if (kw == "BA_DEF_DEF_") {
        skip_ws();
        std::string name = string_lit();
        skip_ws();
        attr_defaults_[name] = value_lit();
        expect(';');
      } else if (kw == "BA_") {
        parse_attr(kw_line);
      } else if (kw == "VAL_") {
        parse_val(kw_line);
      } else if (kw == "SIG_VALTYPE_") {
        parse_valtype(kw_line);
      } else if (kw == "SG_MUL_VAL_") {
        parse_mul_val(kw_line);
      } else {
        // Sections meter does not use (VAL_TABLE_, EV_, BO_TX_BU_, SIG_GROUP_, ...): skip to ';'.
        skip_statement(kw, kw_line);
      }
    }
    finish();
    db_.build_index();
    return std::move(db_);
  }

 private:
  std::string_view s_;
  std::string file_;
  std::size_t pos_ = 0, line_start_ = 0;
  int line_ = 1;
  Database db_;
  std::ptrdiff_t current_ = -1;  // index: the vector grows
  bool current_skipped_ = false;
  std::map<std::string, std::vector<std::string>> enum_defs_;
  std::map<std::string, AttrValue> attr_defaults_;
  std::vector<PendingAttr> attrs_;
  struct Pending {
    int line;
    std::uint32_t raw_id;
    std::string signal;
    std::vector<std::pair<std::int64_t, std::string>> choices;
    int valtype = -1;
    std::string switch_name;
    std::vector<MuxRange> ranges;
    std::string comment;
    char kind;  // 'V' VAL_, 'T' SIG_VALTYPE_, 'M' SG_MUL_VAL_, 'C' comment (signal), 'c' comment (message)
  };
  std::vector<Pending> pending_;

  [[noreturn]] void error(const std::string& what) const { throw DbcError(file_, line_, what); }
  bool eof() const { return pos_ >= s_.size(); }
  char peek() const { return eof() ? '\0' : s_[pos_]; }
  std::string preview() const {
    if (eof()) return "end of file";
    std::string p(s_.substr(pos_, 20));
    auto nl = p.find_first_of("\r\n");
    if (nl != std::string::npos) p.resize(nl);
    return p;
  }
  void newline() {
    ++line_;
    line_start_ = pos_ + 1;
  }
  void skip_ws() {
    while (!eof()) {
      char c = s_[pos_];
      if (c == '\n') {
        newline();
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == '/' && pos_ + 1 < s_.size() && s_[pos_ + 1] == '/') {
        while (!eof() && s_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  void skip_inline_ws() {
    while (!eof() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r')) ++pos_;
  }
  bool eol() const { return eof() || s_[pos_] == '\n'; }
  void skip_line() {
    while (!eof() && s_[pos_] != '\n') ++pos_;
  }
  void expect(char c) {
    skip_ws();
    if (peek() != c) error(std::string("expected '") + c + "' but found '" + preview() + "'");
    ++pos_;
  }
  bool accept(char c) {
    skip_ws();
    if (peek() == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  std::string ident() {
    skip_ws();
    std::size_t b = pos_;
    while (!eof()) {
      char c = s_[pos_];
      if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')
        ++pos_;
      else
        break;
    }
    return std::string(s_.substr(b, pos_ - b));
  }
  std::string need_ident(const char* what) {
    std::string n = ident();
    if (n.empty()) error(std::string("expected ") + what + " but found '" + preview() + "'");
    return n;
  }
  double number(const char* what) {
    skip_ws();
    std::size_t b = pos_;
    if (peek() == '+' || peek() == '-') ++pos_;
    while (!eof()) {
      char c = s_[pos_];
      bool exp_sign = (c == '+' || c == '-') && pos_ > b && (s_[pos_ - 1] == 'e' || s_[pos_ - 1] == 'E');
      if ((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || exp_sign)
        ++pos_;
      else
        break;
    }
    std::string t(s_.substr(b, pos_ - b));
    if (t.empty() || t == "+" || t == "-")
      error(std::string("expected a number for ") + what + " but found '" + preview() + "'");
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size())
      error(std::string("expected a number for ") + what + " but found '" + t + "'");
    return v;
  }
  std::uint64_t uint_lit(const char* what) {
    skip_ws();
    std::size_t b = pos_;
    while (!eof() && s_[pos_] >= '0' && s_[pos_] <= '9') ++pos_;
    if (b == pos_) error(std::string("expected an unsigned integer for ") + what + " but found '" + preview() + "'");
    std::string t(s_.substr(b, pos_ - b));
    errno = 0;
    unsigned long long v = std::strtoull(t.c_str(), nullptr, 10);
    if (errno == ERANGE) error(std::string(what) + ": " + t + " is too large");
    return v;
  }
  std::int64_t int_lit(const char* what) {
    skip_ws();
    bool neg = false;
    if (peek() == '-' || peek() == '+') {
      neg = peek() == '-';
      ++pos_;
    }
    std::uint64_t v = uint_lit(what);
    return neg ? -static_cast<std::int64_t>(v) : static_cast<std::int64_t>(v);
  }
  std::string string_lit() {
    skip_ws();
    if (peek() != '"') error("expected a quoted string but found '" + preview() + "'");
    ++pos_;
    const int start_line = line_;
    std::string out;
    while (true) {
      if (eof()) {
        line_ = start_line;
        error("unterminated string (missing '\"')");
      }
      char c = s_[pos_];
      if (c == '\\' && pos_ + 1 < s_.size()) {
        out += s_[pos_ + 1];
        pos_ += 2;
        continue;
      }
      if (c == '"') {
        ++pos_;
        break;
      }
      if (c == '\n') newline();
      if (c != '\r') out += c;
      ++pos_;
    }
    return out;
  }
  AttrValue value_lit() {
    skip_ws();
    AttrValue v;
    if (peek() == '"') {
      v.is_string = true;
      v.text = string_lit();
    } else {
      v.number = number("attribute value");
    }
    return v;
  }
  void skip_statement(const std::string& kw, int kw_line) {
    while (!eof()) {
      char c = s_[pos_];
      if (c == '"') {
        string_lit();
        continue;
      }
      if (c == '\n') newline();
      ++pos_;
      if (c == ';') return;
    }
    line_ = kw_line;
    error("expected ';' ending the " + kw + " statement started here");
  }

  void parse_message(int kw_line) {
    std::uint64_t raw = uint_lit("message id");
    if (raw > 0xFFFFFFFFull) error("message id does not fit 32 bits");
    std::string name = need_ident("a message name");
    expect(':');
    std::uint64_t size = uint_lit("message size");
    if (size > 64) error("message size " + std::to_string(size) + " is above 64 bytes");
    skip_inline_ws();
    std::string tx = eol() ? std::string() : ident();
    if (raw == kIndependentSignalsId) {
      // Signals without a message: no frame ever carries them.
      current_ = -1;
      current_skipped_ = true;
      return;
    }
    DbcMessage m;
    m.extended = (raw & 0x80000000u) != 0;
    m.id = static_cast<std::uint32_t>(raw & 0x1FFFFFFFu);
    if (!m.extended && m.id > 0x7FF) {
      db_.warnings.push_back({kw_line, "message " + name + ": standard id " + std::to_string(m.id) +
                                           " above 0x7FF; treated as extended"});
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

  void parse_signal(int kw_line) {
    DbcSignal sig;
    sig.line = kw_line;
    sig.name = need_ident("a signal name");
    skip_ws();
    int mux_value = -1;
    if (peek() != ':') {
      std::string m = ident();
      if (m == "M") {
        sig.is_multiplexor = true;
      } else if (m.size() >= 2 && m[0] == 'm') {
        std::size_t i = 1;
        std::uint64_t v = 0;
        while (i < m.size() && m[i] >= '0' && m[i] <= '9') v = v * 10 + static_cast<unsigned>(m[i++] - '0');
        if (i == 1 || (i < m.size() && !(m[i] == 'M' && i + 1 == m.size())))
          error("signal " + sig.name + ": expected multiplexer indicator 'M', 'm<N>' or 'm<N>M' but found '" + m + "'");
        if (i < m.size()) sig.is_multiplexor = true;
        mux_value = static_cast<int>(v);
        sig.mux_ranges.push_back({v, v});
      } else {
        error("signal " + sig.name + ": expected ':' or a multiplexer indicator but found '" + m + "'");
      }
    }
    expect(':');
    std::uint64_t start = uint_lit("start bit");
    expect('|');
    std::uint64_t len = uint_lit("signal length");
    expect('@');
    char order = peek();
    if (order != '0' && order != '1') error("signal " + sig.name + ": expected byte order '@0' (Motorola) or '@1' (Intel)");
    ++pos_;
    char sign = peek();
    if (sign != '+' && sign != '-') error("signal " + sig.name + ": expected '+' (unsigned) or '-' (signed) after the byte order");
    ++pos_;
    expect('(');
    sig.factor = number("factor");
    expect(',');
    sig.offset = number("offset");
    expect(')');
    expect('[');
    sig.minimum = number("minimum");
    expect('|');
    sig.maximum = number("maximum");
    expect(']');
    sig.unit = string_lit();
    skip_inline_ws();
    while (!eol()) {
      if (peek() == ',') {
        ++pos_;
        skip_inline_ws();
        continue;
      }
      std::string r = ident();
      if (r.empty()) error("signal " + sig.name + ": expected receiver node names but found '" + preview() + "'");
      sig.receivers.push_back(r);
      skip_inline_ws();
    }
    if (len == 0 || len > 64) error("signal " + sig.name + ": length " + std::to_string(len) + " is outside 1..64");
    if (start >= 512) error("signal " + sig.name + ": start bit " + std::to_string(start) + " is beyond 64 bytes");
    if (sig.factor == 0.0) error("signal " + sig.name + ": factor 0 would lose every value");
    sig.start_bit = static_cast<std::uint16_t>(start);
    sig.length = static_cast<std::uint16_t>(len);
    sig.little_endian = order == '1';
    sig.is_signed = sign == '-';
    if (current_skipped_) return;
    if (current_ < 0) error("SG_ " + sig.name + " before any BO_ (a signal must follow its message)");
    DbcMessage& cur = db_.messages[static_cast<std::size_t>(current_)];
    if (cur.find_signal(sig.name) >= 0) {
      db_.warnings.push_back({kw_line, "message " + cur.name + ": duplicate signal " + sig.name + " ignored"});
      return;
    }
    if (mux_value >= 0) sig.mux_switch = -2;  // resolved in finish()
    cur.signals.push_back(std::move(sig));
  }

  std::uint32_t message_ref() {
    std::uint64_t raw = uint_lit("message id");
    if (raw > 0xFFFFFFFFull) error("message id does not fit 32 bits");
    return static_cast<std::uint32_t>(raw);
  }

  void parse_comment() {
    skip_ws();
    if (peek() == '"') {
      string_lit();
      expect(';');
      return;
    }
    int l = line_;
    std::string obj = ident();
    if (obj == "BO_") {
      std::uint32_t id = message_ref();
      std::string text = string_lit();
      pending_.push_back({l, id, "", {}, -1, "", {}, text, 'c'});
    } else if (obj == "SG_") {
      std::uint32_t id = message_ref();
      std::string sig = need_ident("a signal name");
      std::string text = string_lit();
      pending_.push_back({l, id, sig, {}, -1, "", {}, text, 'C'});
    } else if (obj == "BU_" || obj == "EV_") {
      ident();
      string_lit();
    } else {
      error("CM_: expected BU_, BO_, SG_, EV_ or a string but found '" + obj + preview() + "'");
    }
    expect(';');
  }

  void parse_attr_def() {
    skip_ws();
    if (peek() != '"') ident();  // object type (BU_, BO_, SG_, EV_)
    std::string name = string_lit();
    std::string type = need_ident("an attribute type (INT, HEX, FLOAT, STRING, ENUM)");
    if (type == "ENUM") {
      std::vector<std::string> values;
      skip_ws();
      while (peek() == '"') {
        values.push_back(string_lit());
        if (!accept(',')) break;
        skip_ws();
      }
      enum_defs_[name] = values;
    } else {
      while (skip_ws(), !eof() && peek() != ';') {
        if (peek() == '"') string_lit();
        else number("attribute limit");
      }
    }
    expect(';');
  }

  void parse_attr(int kw_line) {
    PendingAttr a;
    a.line = kw_line;
    a.name = string_lit();
    skip_ws();
    if (peek() == '"' || peek() == '-' || peek() == '+' || peek() == '.' || (peek() >= '0' && peek() <= '9')) {
      a.object = 'G';
    } else {
      std::string obj = ident();
      if (obj == "BO_") {
        a.object = 'B';
        a.raw_id = message_ref();
      } else if (obj == "SG_") {
        a.object = 'S';
        a.raw_id = message_ref();
        a.signal = need_ident("a signal name");
      } else if (obj == "BU_" || obj == "EV_") {
        a.object = 'N';
        ident();
      } else if (obj == "BU_BO_REL_" || obj == "BU_SG_REL_" || obj == "BU_EV_REL_") {
        skip_statement("BA_", kw_line);
        return;
      } else {
        error("BA_ \"" + a.name + "\": expected BU_, BO_, SG_, EV_ or a value but found '" + obj + "'");
      }
    }
    a.value = value_lit();
    expect(';');
    attrs_.push_back(std::move(a));
  }

  void parse_val(int kw_line) {
    skip_ws();
    if (!(peek() >= '0' && peek() <= '9')) {  // VAL_ for an environment variable
      skip_statement("VAL_", kw_line);
      return;
    }
    Pending p{kw_line, message_ref(), need_ident("a signal name"), {}, -1, "", {}, "", 'V'};
    while (skip_ws(), !eof() && peek() != ';') {
      double raw = number("value table entry");
      if (!(raw >= -9.2e18 && raw <= 9.2e18)) error("VAL_: value " + std::to_string(raw) + " does not fit 64 bits");
      auto v = static_cast<std::int64_t>(raw);
      p.choices.emplace_back(v, string_lit());
    }
    expect(';');
    pending_.push_back(std::move(p));
  }

  void parse_valtype(int kw_line) {
    Pending p{kw_line, message_ref(), need_ident("a signal name"), {}, -1, "", {}, "", 'T'};
    accept(':');
    std::uint64_t t = uint_lit("SIG_VALTYPE_ (0 integer, 1 float, 2 double)");
    if (t > 2) error("SIG_VALTYPE_: expected 0, 1 or 2 but found " + std::to_string(t));
    p.valtype = static_cast<int>(t);
    expect(';');
    pending_.push_back(std::move(p));
  }

  void parse_mul_val(int kw_line) {
    Pending p{kw_line, message_ref(), need_ident("a signal name"), {}, -1, "", {}, "", 'M'};
    p.switch_name = need_ident("the multiplexor signal name");
    while (skip_ws(), !eof() && peek() != ';') {
      std::uint64_t lo = uint_lit("multiplexor range start");
      expect('-');
      std::uint64_t hi = uint_lit("multiplexor range end");
      if (hi < lo) error("SG_MUL_VAL_: range " + std::to_string(lo) + "-" + std::to_string(hi) + " is reversed");
      p.ranges.push_back({lo, hi});
      if (!accept(',')) break;
    }
    expect(';');
    pending_.push_back(std::move(p));
  }

  DbcMessage* message_by_raw(std::uint32_t raw) {
    bool ext = (raw & 0x80000000u) != 0;
    std::uint32_t id = raw & 0x1FFFFFFFu;
    for (auto& m : db_.messages)
      if (m.id == id && (m.extended == ext || (!ext && id > 0x7FF))) return &m;
    return nullptr;
  }

  std::optional<std::string> enum_text(const std::string& name, const AttrValue& v) {
    if (v.is_string) return v.text;
    auto it = enum_defs_.find(name);
    if (it == enum_defs_.end()) return std::nullopt;
    auto idx = static_cast<std::size_t>(v.number);
    if (v.number < 0 || idx >= it->second.size()) return std::nullopt;
    return it->second[idx];
  }

  void finish() {
    // Value tables, value types, comments, extended multiplexing.
    for (auto& p : pending_) {
      DbcMessage* m = message_by_raw(p.raw_id);
      if (!m) {
        if ((p.raw_id & 0xFFFFFFFFu) != kIndependentSignalsId)
          db_.warnings.push_back({p.line, "reference to unknown message id " + std::to_string(p.raw_id) + " ignored"});
        continue;
      }
      if (p.kind == 'c') {
        m->comment = p.comment;
        continue;
      }
      int si = m->find_signal(p.signal);
      if (si < 0) {
        db_.warnings.push_back({p.line, "reference to unknown signal " + m->name + "." + p.signal + " ignored"});
        continue;
      }
      DbcSignal& s = m->signals[static_cast<std::size_t>(si)];
      switch (p.kind) {
        case 'C': s.comment = p.comment; break;
        case 'V': s.choices = p.choices; break;
        case 'T':
          if (p.valtype == 1 && s.length != 32) {
            line_ = p.line;
            error("SIG_VALTYPE_ " + m->name + "." + s.name + ": IEEE float needs a 32-bit signal, it has " + std::to_string(s.length));
          }
          if (p.valtype == 2 && s.length != 64) {
            line_ = p.line;
            error("SIG_VALTYPE_ " + m->name + "." + s.name + ": IEEE double needs a 64-bit signal, it has " + std::to_string(s.length));
          }
          s.value_type = p.valtype == 1 ? ValueType::Float32 : p.valtype == 2 ? ValueType::Float64 : ValueType::Integer;
          break;
        case 'M': {
          int sw = m->find_signal(p.switch_name);
          if (sw < 0 || !m->signals[static_cast<std::size_t>(sw)].is_multiplexor) {
            line_ = p.line;
            error("SG_MUL_VAL_ " + m->name + "." + s.name + ": expected a multiplexor signal, '" + p.switch_name + "' is not one");
          }
          s.mux_switch = sw;
          s.mux_ranges = p.ranges;
          break;
        }
        default: break;
      }
    }
    // Simple multiplexing: mN signals switch on the message's plain 'M' signal.
    for (auto& m : db_.messages) {
      int plain = -1;
      for (std::size_t i = 0; i < m.signals.size(); ++i)
        if (m.signals[i].is_multiplexor && m.signals[i].mux_ranges.empty()) plain = static_cast<int>(i);
      for (auto& s : m.signals) {
        if (s.mux_switch != -2) continue;
        if (plain < 0) {
          line_ = s.line;
          error("signal " + m.name + "." + s.name + " is multiplexed (m<N>) but the message has no multiplexor 'M' signal");
        }
        s.mux_switch = plain;
      }
      for (std::size_t i = 0; i < m.signals.size(); ++i) {
        const auto& s = m.signals[i];
        if (s.bytes_needed() > m.size)
          db_.warnings.push_back({s.line, "signal " + m.name + "." + s.name + " reaches byte " +
                                              std::to_string(s.bytes_needed()) + " of a " + std::to_string(m.size) + "-byte message"});
      }
    }
    // Attributes: defaults first, then per-object values.
    auto apply_msg_attr = [&](DbcMessage& m, const std::string& name, const AttrValue& v) {
      if (name == "GenMsgCycleTime" && !v.is_string) {
        if (v.number > 0) m.cycle_time_ms = static_cast<int>(v.number);
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
    for (auto& m : db_.messages) {
      for (auto& [name, v] : attr_defaults_) apply_msg_attr(m, name, v);
      if (db_.protocol_type == "J1939") m.j1939 = true;
      if (!m.extended) m.j1939 = false;
    }
    for (auto& a : attrs_) {
      if (a.object != 'B') continue;
      DbcMessage* m = message_by_raw(a.raw_id);
      if (!m) {
        if (a.raw_id != kIndependentSignalsId)
          db_.warnings.push_back({a.line, "BA_ \"" + a.name + "\" for unknown message id " + std::to_string(a.raw_id) + " ignored"});
        continue;
      }
      apply_msg_attr(*m, a.name, a.value);
      if (!m->extended) m->j1939 = false;
    }
  }
};

}  // namespace

Database parse_dbc(std::string_view text, const std::string& file) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
      static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF)
    text.remove_prefix(3);
  if (!valid_utf8(text)) {
    std::string converted = cp1252_to_utf8(text);
    return Parser(converted, file).run();
  }
  return Parser(text, file).run();
}

Database load_dbc(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DbcError(path, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_dbc(ss.str(), path);
}

}  // namespace meter::controller
