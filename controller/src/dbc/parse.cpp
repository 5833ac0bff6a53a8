// DBC parser. Written against the file grammar (Vector's DBC format description) and the quirks
// of real files: "SG_ X:" without a space, "(0.1, 0)" with spaces, // comments, CRLF, cp1252 text,
// the VECTOR__INDEPENDENT_SIG_MSG pseudo message, and sections it does not need (skipped by ';').
// This file: the entry points (encoding detection, file loading) and the statement dispatch.
#include <fstream>
#include <sstream>

#include "parser.hpp"
#include "text_encoding.hpp"

namespace meter::controller::dbc_parse {

Database DbcParser::run() {
  db_.file = lex_.file();
  for (;;) {
    lex_.skip_ws();
    if (lex_.eof()) break;
    int kw_line = lex_.line();
    std::string kw = lex_.ident();
    if (kw.empty()) lex_.error("expected a keyword (BO_, SG_, CM_, BA_, VAL_, ...) but found '" + lex_.preview() + "'");
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
      while (lex_.skip_inline_ws(), !lex_.eol()) {
        std::string n = lex_.ident();
        if (n.empty()) lex_.error("BU_: expected a node name");
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
      lex_.skip_ws();
      std::string name = lex_.string_lit();
      lex_.skip_ws();
      attr_defaults_[name] = value_lit();
      lex_.expect(';');
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
      lex_.skip_statement(kw, kw_line);
    }
  }
  finish();
  db_.build_index();
  return std::move(db_);
}

}  // namespace meter::controller::dbc_parse

namespace meter::controller {

Database parse_dbc(std::string_view text, const std::string& file) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF &&
      static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF)
    text.remove_prefix(3);
  if (!dbc_parse::valid_utf8(text)) {
    std::string converted = dbc_parse::cp1252_to_utf8(text);
    return dbc_parse::DbcParser(converted, file).run();
  }
  return dbc_parse::DbcParser(text, file).run();
}

Database load_dbc(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DbcError(path, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_dbc(ss.str(), path);
}

}  // namespace meter::controller
