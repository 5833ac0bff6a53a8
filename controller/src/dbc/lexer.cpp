// DBC tokens: identifiers, numbers, quoted strings, punctuation, // comments and line tracking.
#include "lexer.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace meter::controller::dbc_parse {

std::string DbcLexer::preview() const {
  if (eof()) return "end of file";
  std::string p(s_.substr(pos_, 20));
  auto nl = p.find_first_of("\r\n");
  if (nl != std::string::npos) p.resize(nl);
  return p;
}

void DbcLexer::newline() {
  ++line_;
  line_start_ = pos_ + 1;
}

void DbcLexer::skip_ws() {
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

void DbcLexer::skip_inline_ws() {
  while (!eof() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r')) ++pos_;
}

void DbcLexer::skip_line() {
  while (!eof() && s_[pos_] != '\n') ++pos_;
}

void DbcLexer::expect(char c) {
  skip_ws();
  if (peek() != c) error(std::string("expected '") + c + "' but found '" + preview() + "'");
  ++pos_;
}

bool DbcLexer::accept(char c) {
  skip_ws();
  if (peek() == c) {
    ++pos_;
    return true;
  }
  return false;
}

std::string DbcLexer::ident() {
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

std::string DbcLexer::need_ident(const char* what) {
  std::string n = ident();
  if (n.empty()) error(std::string("expected ") + what + " but found '" + preview() + "'");
  return n;
}

double DbcLexer::number(const char* what) {
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
  // strtod gives +-HUGE_VAL (inf) past the largest double; an inf factor, offset or limit would turn
  // every decoded value into inf or NaN. Underflow (a tiny value read as 0 or subnormal) is kept.
  if (!std::isfinite(v)) error(std::string("number for ") + what + " is too large for a double: '" + t + "'");
  return v;
}

std::uint64_t DbcLexer::uint_lit(const char* what) {
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

std::string DbcLexer::string_lit() {
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

bool DbcLexer::skip_statement() {
  while (!eof()) {
    char c = s_[pos_];
    if (c == '"') {
      string_lit();
      continue;
    }
    if (c == '\n') {
      newline();
      ++pos_;
      if (at_statement_start()) return false;
      continue;
    }
    ++pos_;
    if (c == ';') return true;
  }
  return false;
}

bool DbcLexer::token_starts_line() const {
  for (std::size_t i = line_start_; i < pos_; ++i)
    if (s_[i] != ' ' && s_[i] != '\t' && s_[i] != '\r') return false;
  return true;
}

bool DbcLexer::at_statement_start() {
  skip_ws();
  if (eof()) return true;
  if (!token_starts_line()) return false;
  std::size_t e = pos_;
  while (e < s_.size() && ((s_[e] >= 'A' && s_[e] <= 'Z') || s_[e] == '_')) ++e;
  return is_keyword(s_.substr(pos_, e - pos_));
}

void DbcLexer::resync() {
  for (;;) {
    skip_line();
    if (eof()) return;
    newline();
    ++pos_;
    if (at_statement_start()) return;
  }
}

bool is_keyword(std::string_view w) {
  static constexpr std::string_view kKeywords[] = {
      "VERSION", "NS_", "BS_", "BU_", "BO_", "SG_", "CM_", "BA_DEF_", "BA_DEF_DEF_", "BA_", "VAL_",
      "VAL_TABLE_", "SIG_VALTYPE_", "SG_MUL_VAL_", "SIG_GROUP_", "EV_", "ENVVAR_DATA_", "BO_TX_BU_",
      "BA_DEF_REL_", "BA_DEF_DEF_REL_", "BA_REL_", "BA_DEF_SGTYPE_", "SGTYPE_", "SIG_TYPE_REF_",
      "SIGTYPE_VALTYPE_", "SGTYPE_VAL_", "BA_SGTYPE_", "CAT_DEF_", "CAT_", "FILTER", "EV_DATA_",
      "BU_SG_REL_", "BU_EV_REL_", "BU_BO_REL_", "NS_DESC_"};
  for (auto k : kKeywords)
    if (k == w) return true;
  return false;
}


}  // namespace meter::controller::dbc_parse
