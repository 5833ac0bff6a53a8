// DBC parser. Written against the file grammar (Vector's DBC format description) and the quirks
// of real files: "SG_ X:" without a space, "(0.1, 0)" with spaces, // comments, CRLF, cp1252 text,
// the VECTOR__INDEPENDENT_SIG_MSG pseudo message, and sections it does not need (skipped by ';').
// This file: the entry points (encoding detection, file loading) and the statement dispatch.
#include <algorithm>
#include <fstream>
#include <sstream>

#include "meter/controller/dbc/parse.hpp"
#include "parser.hpp"
#include "text_encoding.hpp"

namespace meter::controller::dbc_parse {

Database DbcParser::run() {
  db_.file = lex_.file();
  for (;;) {
    lex_.skip_ws();
    if (lex_.eof()) break;
    const int kw_line = lex_.line();
    std::string kw = lex_.ident();
    try {
      if (kw.empty()) lex_.error("expected a keyword (BO_, SG_, CM_, BA_, VAL_, ...) but found '" + lex_.preview() + "'");
      statement(kw, kw_line);
    } catch (const DbcError& e) {
      skip_broken(kw, kw_line, e);
      lex_.resync();
    }
  }
  finish();
  db_.build_index();
  std::stable_sort(db_.warnings.begin(), db_.warnings.end(),
                   [](const DbcWarning& a, const DbcWarning& b) { return a.line < b.line; });
  return std::move(db_);
}

void DbcParser::statement(const std::string& kw, int kw_line) {
  if (kw == "VERSION") {
    lex_.skip_ws();
    db_.version = lex_.string_lit();
  } else if (kw == "NS_") {
    lex_.expect(':');
    // The NS_ list is indented; it ends at the first token that starts a line.
    for (;;) {
      lex_.skip_ws();
      if (lex_.eof() || lex_.at_line_start()) break;
      if (lex_.ident().empty()) lex_.error("NS_: expected a keyword name");
    }
  } else if (kw == "BS_") {
    lex_.expect(':');
    lex_.skip_line();
  } else if (kw == "BU_") {
    lex_.expect(':');
    // Node names, on the BU_ line or indented on the lines after it (one per line).
    while (!lex_.at_statement_start()) {
      std::string n = lex_.ident();
      if (n.empty()) lex_.error("BU_: expected a node name but found '" + lex_.preview() + "'");
      db_.nodes.push_back(n);
    }
  } else if (kw == "BO_") {
    parse_message(kw_line);
  } else if (kw == "SG_") {
    parse_signal(kw_line);
  } else if (kw == "CM_") {
    parse_comment(kw_line);
  } else if (kw == "BA_DEF_") {
    parse_attr_def(kw_line);
  } else if (kw == "BA_DEF_DEF_") {
    lex_.skip_ws();
    std::string name = lex_.string_lit();
    lex_.skip_ws();
    attr_defaults_[name] = value_lit();
    attr_default_lines_[name] = kw_line;
    end_statement("BA_DEF_DEF_", kw_line);
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
    if (!lex_.skip_statement()) warn_missing_semicolon(kw, kw_line);
  }
}

void DbcParser::end_statement(const char* kw, int kw_line) {
  if (lex_.accept(';')) return;
  if (!lex_.at_statement_start()) lex_.error(std::string("expected ';' ending the ") + kw + " statement but found '" + lex_.preview() + "'");
  warn_missing_semicolon(kw, kw_line);
}

void DbcParser::warn_missing_semicolon(const std::string& kw, int kw_line) {
  warn(DbcWarningKind::MissingSemicolon, kw_line, kw + " has no ';': assumed to end before line " + std::to_string(lex_.line()));
}

void DbcParser::skip_broken(const std::string& kw, int kw_line, const DbcError& e) {
  std::string reason = e.what();
  // The message without the "file:" prefix: the warning names its own line.
  if (auto c = reason.find(": ", lex_.file().size()); reason.rfind(lex_.file(), 0) == 0 && c != std::string::npos)
    reason = reason.substr(c + 2);
  if (kw == "BO_") {
    // The signals that follow belong to the broken message: skipped with it, never attached to
    // the message before.
    current_ = -1;
    current_skipped_ = true;
    skipped_message_ = defining_name_.empty() ? "line " + std::to_string(kw_line) : defining_name_;
    skipped_message_line_ = kw_line;
    db_.skipped.push_back({skipped_message_, "", kw_line, reason});
    warn(DbcWarningKind::SkippedStatement, kw_line, "BO_ skipped with its signals: " + reason);
  } else if (kw == "SG_") {
    std::string msg = current_ >= 0 ? db_.messages[static_cast<std::size_t>(current_)].name : skipped_message_;
    if (!defining_name_.empty()) db_.skipped.push_back({msg, defining_name_, kw_line, reason});
    warn(DbcWarningKind::SkippedStatement, kw_line, "SG_ skipped: " + reason);
  } else {
    warn(DbcWarningKind::SkippedStatement, kw_line, (kw.empty() ? std::string("statement") : kw) + " skipped: " + reason);
  }
  defining_name_.clear();
}

}  // namespace meter::controller::dbc_parse

namespace meter::controller {

Database parse_dbc(std::string_view text, const std::string& file, const DbcOptions& options) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
      static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF)
    text.remove_prefix(3);
  Database db;
  if (const std::size_t bad = dbc_parse::first_invalid_utf8(text); bad != std::string_view::npos) {
    std::string converted = dbc_parse::cp1252_to_utf8(text);
    db = dbc_parse::DbcParser(converted, file).run();
    // The line of the first byte that is not UTF-8, so the user can look at what was converted.
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n'));
    db.warnings.insert(db.warnings.begin(),
                       DbcWarning{DbcWarningKind::NotUtf8, line, "the text is not UTF-8 (first at this line): read as Windows-1252"});
  } else {
    db = dbc_parse::DbcParser(text, file).run();
  }
  if (options.strict && !db.warnings.empty()) {
    std::string what = std::to_string(db.warnings.size()) + " problem(s) refused by --strict:";
    for (const auto& w : db.warnings)
      what += "\n  " + file + ":" + std::to_string(w.line) + ": [" + to_string(w.kind) + "] " + w.text;
    throw DbcError(file, db.warnings.front().line, what);
  }
  return db;
}

Database load_dbc(const std::string& path, const DbcOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DbcError(path, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_dbc(ss.str(), path, options);
}

}  // namespace meter::controller
