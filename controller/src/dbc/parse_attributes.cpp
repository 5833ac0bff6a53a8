// Statements that refer to messages and signals by id: CM_ comments, BA_DEF_ / BA_ attributes,
// VAL_ value tables, SIG_VALTYPE_ float types and SG_MUL_VAL_ extended multiplexing. They are
// recorded here and applied in resolve.cpp, since a DBC may name a message before defining it.
#include "parser.hpp"

namespace meter::controller::dbc_parse {

std::uint32_t DbcParser::message_ref() {
  std::uint64_t raw = lex_.uint_lit("message id");
  if (raw > 0xFFFFFFFFull) lex_.error("message id does not fit 32 bits");
  return static_cast<std::uint32_t>(raw);
}

AttrValue DbcParser::value_lit() {
  lex_.skip_ws();
  AttrValue v;
  if (lex_.peek() == '"') {
    v.is_string = true;
    v.text = lex_.string_lit();
  } else {
    v.number = lex_.number("attribute value");
  }
  return v;
}

void DbcParser::parse_comment(int kw_line) {
  lex_.skip_ws();
  if (lex_.peek() == '"') {
    lex_.string_lit();
    end_statement("CM_", kw_line);
    return;
  }
  int l = lex_.line();
  if (lex_.peek() >= '0' && lex_.peek() <= '9') {
    std::uint32_t id = message_ref();
    std::string text = lex_.string_lit();
    warn(DbcWarningKind::UnnamedComment, l, "CM_ " + std::to_string(id) + " names no object (BO_, SG_, ...): taken as a comment on message " + std::to_string(id));
    pending_.push_back({l, id, "", {}, -1, "", {}, text, 'c'});
    end_statement("CM_", kw_line);
    return;
  }
  std::string obj = lex_.ident();
  if (obj == "BO_") {
    std::uint32_t id = message_ref();
    std::string text = lex_.string_lit();
    pending_.push_back({l, id, "", {}, -1, "", {}, text, 'c'});
  } else if (obj == "SG_") {
    std::uint32_t id = message_ref();
    lex_.skip_ws();
    if (lex_.peek() == '"') {
      std::string text = lex_.string_lit();
      warn(DbcWarningKind::UnnamedComment, l, "CM_ SG_ " + std::to_string(id) + " names no signal: taken as a comment on message " + std::to_string(id));
      pending_.push_back({l, id, "", {}, -1, "", {}, text, 'c'});
    } else {
      std::string sig = lex_.need_ident("a signal name");
      std::string text = lex_.string_lit();
      pending_.push_back({l, id, sig, {}, -1, "", {}, text, 'C'});
    }
  } else if (obj == "BU_" || obj == "EV_") {
    lex_.need_ident(obj == "BU_" ? "a node name" : "an environment variable name");
    lex_.string_lit();
  } else {
    lex_.error("CM_: expected BU_, BO_, SG_, EV_ or a string but found '" + obj + lex_.preview() + "'");
  }
  end_statement("CM_", kw_line);
}

void DbcParser::parse_attr_def(int kw_line) {
  lex_.skip_ws();
  if (lex_.peek() != '"') lex_.ident();  // object type (BU_, BO_, SG_, EV_)
  std::string name = lex_.string_lit();
  std::string type = lex_.need_ident("an attribute type (INT, HEX, FLOAT, STRING, ENUM)");
  if (enum_defs_.count(name) || declared_attrs_.count(name))
    warn(DbcWarningKind::Duplicate, kw_line, "BA_DEF_ \"" + name + "\" defined again: the last definition wins");
  declared_attrs_.insert(name);
  if (type == "ENUM") {
    std::vector<std::string> values;
    lex_.skip_ws();
    while (lex_.peek() == '"') {
      values.push_back(lex_.string_lit());
      if (!lex_.accept(',')) break;
      lex_.skip_ws();
    }
    enum_defs_[name] = values;
  } else {
    enum_defs_.erase(name);
    if (type != "INT" && type != "HEX" && type != "FLOAT" && type != "STRING")
      warn(DbcWarningKind::UnknownAttributeType, kw_line,
           "BA_DEF_ \"" + name + "\": unknown type " + type + " (expected INT, HEX, FLOAT, STRING or ENUM); its values are read as given");
    while (!lex_.at_statement_start() && lex_.peek() != ';') {
      if (lex_.peek() == '"') lex_.string_lit();
      else lex_.number("attribute limit");
    }
  }
  end_statement("BA_DEF_", kw_line);
}

void DbcParser::parse_attr(int kw_line) {
  PendingAttr a;
  a.line = kw_line;
  a.name = lex_.string_lit();
  lex_.skip_ws();
  if (lex_.peek() == '"' || lex_.peek() == '-' || lex_.peek() == '+' || lex_.peek() == '.' || (lex_.peek() >= '0' && lex_.peek() <= '9')) {
    a.object = 'G';
  } else {
    std::string obj = lex_.ident();
    if (obj == "BO_") {
      a.object = 'B';
      a.raw_id = message_ref();
    } else if (obj == "SG_") {
      a.object = 'S';
      a.raw_id = message_ref();
      a.signal = lex_.need_ident("a signal name");
    } else if (obj == "BU_" || obj == "EV_") {
      a.object = 'N';
      lex_.ident();
    } else if (obj == "BU_BO_REL_" || obj == "BU_SG_REL_" || obj == "BU_EV_REL_") {
      if (!lex_.skip_statement()) warn_missing_semicolon("BA_", kw_line);
      return;
    } else {
      lex_.error("BA_ \"" + a.name + "\": expected BU_, BO_, SG_, EV_ or a value but found '" + obj + "'");
    }
  }
  a.value = value_lit();
  end_statement("BA_", kw_line);
  attrs_.push_back(std::move(a));
}

void DbcParser::parse_val(int kw_line) {
  lex_.skip_ws();
  if (!(lex_.peek() >= '0' && lex_.peek() <= '9')) {  // VAL_ for an environment variable
    if (!lex_.skip_statement()) warn_missing_semicolon("VAL_", kw_line);
    return;
  }
  PendingRef p{kw_line, message_ref(), lex_.need_ident("a signal name"), {}, -1, "", {}, "", 'V'};
  while (!lex_.at_statement_start() && lex_.peek() != ';') {
    double raw = lex_.number("value table entry");
    if (!(raw >= -9.2e18 && raw <= 9.2e18)) lex_.error("VAL_: value " + std::to_string(raw) + " does not fit 64 bits");
    auto v = static_cast<std::int64_t>(raw);
    p.choices.emplace_back(v, lex_.string_lit());
  }
  end_statement("VAL_", kw_line);
  pending_.push_back(std::move(p));
}

void DbcParser::parse_valtype(int kw_line) {
  PendingRef p{kw_line, message_ref(), lex_.need_ident("a signal name"), {}, -1, "", {}, "", 'T'};
  lex_.accept(':');
  std::uint64_t t = lex_.uint_lit("SIG_VALTYPE_ (0 integer, 1 float, 2 double)");
  if (t > 2) lex_.error("SIG_VALTYPE_: expected 0, 1 or 2 but found " + std::to_string(t));
  p.valtype = static_cast<int>(t);
  end_statement("SIG_VALTYPE_", kw_line);
  pending_.push_back(std::move(p));
}

void DbcParser::parse_mul_val(int kw_line) {
  PendingRef p{kw_line, message_ref(), lex_.need_ident("a signal name"), {}, -1, "", {}, "", 'M'};
  p.switch_name = lex_.need_ident("the multiplexor signal name");
  while (!lex_.at_statement_start() && lex_.peek() != ';') {
    std::uint64_t lo = lex_.uint_lit("multiplexor range start");
    lex_.expect('-');
    std::uint64_t hi = lex_.uint_lit("multiplexor range end");
    if (hi < lo) lex_.error("SG_MUL_VAL_: range " + std::to_string(lo) + "-" + std::to_string(hi) + " is reversed");
    p.ranges.push_back({lo, hi});
    if (!lex_.accept(',')) break;
  }
  end_statement("SG_MUL_VAL_", kw_line);
  pending_.push_back(std::move(p));
}

}  // namespace meter::controller::dbc_parse
