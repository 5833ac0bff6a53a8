// The DBC statement parser. One pass over the statements (dbc/parse.cpp dispatches them):
// BO_ / SG_ lines build the messages (parse_messages.cpp); CM_, BA_DEF_, BA_, VAL_, SIG_VALTYPE_
// and SG_MUL_VAL_ may name a message before or after it is defined, so they are recorded
// (parse_attributes.cpp) and resolved against the finished message list at the end
// (resolve.cpp), which also checks multiplexing and signal layouts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "lexer.hpp"
#include "meter/controller/dbc/database.hpp"

namespace meter::controller::dbc_parse {

inline constexpr std::uint32_t kIndependentSignalsId = 0xC0000000u;  // VECTOR__INDEPENDENT_SIG_MSG

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

// A statement about a signal or message that is applied once every message is known.
struct PendingRef {
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

class DbcParser {
 public:
  DbcParser(std::string_view text, std::string file) : lex_(text, std::move(file)) {}
  Database run();

 private:
  void statement(const std::string& kw, int kw_line);
  void warn(DbcWarningKind kind, int line, std::string text) { db_.warnings.push_back({kind, line, std::move(text)}); }
  // The ';' that ends a statement; a missing one is a warning when the next line starts a statement.
  void end_statement(const char* kw, int kw_line);
  void warn_missing_semicolon(const std::string& kw, int kw_line);
  // A statement that could not be understood: a warning, and a BO_/SG_ is remembered as skipped.
  void skip_broken(const std::string& kw, int kw_line, const DbcError& e);
  // Messages and signals (parse_messages.cpp).
  void parse_message(int kw_line);
  void parse_signal(int kw_line);
  // Comments, attributes, value tables, value types, extended multiplexing (parse_attributes.cpp).
  std::uint32_t message_ref();
  AttrValue value_lit();
  void parse_comment(int kw_line);
  void parse_attr_def(int kw_line);
  void parse_attr(int kw_line);
  void parse_val(int kw_line);
  void parse_valtype(int kw_line);
  void parse_mul_val(int kw_line);
  // Resolution once every message is known (resolve.cpp).
  DbcMessage* message_by_raw(std::uint32_t raw);
  std::optional<std::string> enum_text(const std::string& name, const AttrValue& v);
  void finish();
  // The stages of finish(), in order. The statements that name a signal (VAL_, SIG_VALTYPE_, CM_,
  // SG_MUL_VAL_) applied to it, unknown references warned about:
  void apply_signal_statements();
  // Simple multiplexing: the mN signals switch on their message's plain 'M' signal.
  void resolve_plain_multiplexing();
  // Attributes: defaults first, then per-object values (cycle times, J1939 and FD frame formats).
  void apply_attributes();
  bool independent(std::uint32_t raw) const { return raw == kIndependentSignalsId || raw == independent_raw_; }

  DbcLexer lex_;
  Database db_;
  std::ptrdiff_t current_ = -1;  // index: the vector grows
  bool current_skipped_ = false;
  std::uint32_t independent_raw_ = kIndependentSignalsId;  // the id the pseudo message was given
  std::string skipped_message_;  // name of the BO_ being skipped (its SG_ lines are skipped too)
  int skipped_message_line_ = 0;
  std::string defining_name_;    // the BO_ or SG_ being parsed, for the skip record
  std::map<std::string, std::vector<std::string>> enum_defs_;
  std::map<std::string, AttrValue> attr_defaults_;
  std::map<std::string, int> attr_default_lines_;  // the BA_DEF_DEF_ line of each default
  std::set<std::string> declared_attrs_;
  std::vector<PendingAttr> attrs_;
  std::vector<PendingRef> pending_;
  // (id | extended << 32) -> the first message with it, in file order; built by finish() so
  // resolving the references takes one lookup each, not a scan of every message.
  std::unordered_map<std::uint64_t, std::size_t> first_by_id_;
};

}  // namespace meter::controller::dbc_parse
