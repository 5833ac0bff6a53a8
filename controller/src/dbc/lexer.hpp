// Tokens of the DBC grammar (Vector's DBC format description): identifiers, numbers, quoted
// strings with escapes, punctuation, '//' comments and CRLF, with the line number every error names.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "meter/controller/dbc/database.hpp"

namespace meter::controller::dbc_parse {

bool is_keyword(std::string_view word);  // a statement keyword of the DBC grammar

class DbcLexer {
 public:
  DbcLexer(std::string_view text, std::string file) : s_(text), file_(std::move(file)) {}

  [[noreturn]] void error(const std::string& what) const { throw DbcError(file_, line_, what); }
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  bool eof() const { return pos_ >= s_.size(); }
  char peek() const { return eof() ? '\0' : s_[pos_]; }
  void advance() { ++pos_; }
  bool at_line_start() const { return pos_ == line_start_; }
  bool eol() const { return eof() || s_[pos_] == '\n'; }
  std::string preview() const;  // the rest of the line (up to 20 characters) for error messages

  void skip_ws();         // blanks, newlines and '//' comments
  void skip_inline_ws();  // blanks on this line only
  void skip_line();
  void expect(char c);
  bool accept(char c);
  std::string ident();  // empty when the next token is not an identifier
  std::string need_ident(const char* what);
  double number(const char* what);
  std::uint64_t uint_lit(const char* what);
  std::string string_lit();
  // Skips a statement meter does not use, up to its ';' (strings may hold ';'). Returns false when
  // a line starting with a keyword came first (the ';' is missing; the lexer stops before it).
  bool skip_statement();
  // True when the next token (after blanks) is the first on its line and is a DBC keyword
  // (BO_, SG_, CM_, VAL_, ...) or the end of the file: where a statement without ';' ends.
  bool at_statement_start();
  // After a statement that could not be understood: moves to the next line that starts with a
  // keyword (SG_ lines included).
  void resync();

 private:
  void newline();
  bool token_starts_line() const;

  std::string_view s_;
  std::string file_;
  std::size_t pos_ = 0, line_start_ = 0;
  int line_ = 1;
};

}  // namespace meter::controller::dbc_parse
