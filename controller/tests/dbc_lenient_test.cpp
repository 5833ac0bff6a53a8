// The lenient DBC parser: each quirk real files carry is read with a warning of its kind naming the
// line and what was assumed; a broken statement is skipped without losing the rest of the file;
// --strict refuses every one of them.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/controller/run/check_dbc_command.hpp"
#include "meter/controller/run/decode_command.hpp"

using namespace meter::controller;

namespace {

const DbcWarning* warning(const Database& db, DbcWarningKind kind, int line) {
  for (const auto& w : db.warnings)
    if (w.kind == kind && w.line == line) return &w;
  return nullptr;
}

void expect_strict_refuses(const std::string& text, int line) {
  try {
    parse_dbc(text, "q.dbc", DbcOptions{true});
    ADD_FAILURE() << "--strict accepted:\n" << text;
  } catch (const DbcError& e) {
    EXPECT_NE(std::string(e.what()).find("q.dbc:" + std::to_string(line) + ": ["), std::string::npos) << e.what();
  }
}

const char* kTwoMessages =
    "BO_ 100 A: 8 X\n"
    " SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\n"
    "BO_ 200 B: 8 X\n"
    " SG_ T : 0|8@1+ (1,0) [0|0] \"\" X\n";

}  // namespace

TEST(DbcLenient, MissingSemicolonEndsTheStatementWithItsLine) {
  std::string t = std::string(kTwoMessages) +
                  "CM_ \"general comment\"\n"             // line 5
                  "VAL_ 100 S 1 \"on\" 0 \"off\"\n"         // line 6: the next line is not read into it
                  "VAL_ 200 T 2 \"two\" ;\n";
  Database db = parse_dbc(t, "q.dbc");
  ASSERT_NE(warning(db, DbcWarningKind::MissingSemicolon, 5), nullptr);
  const DbcWarning* w = warning(db, DbcWarningKind::MissingSemicolon, 6);
  ASSERT_NE(w, nullptr);
  EXPECT_NE(w->text.find("assumed to end before line 7"), std::string::npos) << w->text;
  EXPECT_EQ(db.find("A")->signals[0].choices.size(), 2u);
  EXPECT_EQ(db.find("B")->signals[0].choices.size(), 1u);
  expect_strict_refuses(t, 5);
}

TEST(DbcLenient, MissingSemicolonBeforeAMessage) {
  // A comment without ';' right before a BO_: the message and its signals are still read.
  std::string t = "CM_ \"Front target\"\n" + std::string(kTwoMessages);
  Database db = parse_dbc(t, "q.dbc");
  ASSERT_EQ(db.messages.size(), 2u);
  EXPECT_EQ(db.find("A")->signals.size(), 1u);
  EXPECT_NE(warning(db, DbcWarningKind::MissingSemicolon, 1), nullptr);
}

TEST(DbcLenient, CommentsNamingNoObjectGoToTheMessage) {
  std::string t = std::string(kTwoMessages) + "CM_ SG_ 100 \"names no signal\";\nCM_ 200 \"bare id\";\n";
  Database db = parse_dbc(t, "q.dbc");
  EXPECT_EQ(db.find("A")->comment, "names no signal");
  EXPECT_EQ(db.find("B")->comment, "bare id");
  EXPECT_NE(warning(db, DbcWarningKind::UnnamedComment, 5), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::UnnamedComment, 6), nullptr);
  expect_strict_refuses(t, 5);
}

TEST(DbcLenient, UnknownObjectsDuplicatesAndIds) {
  std::string t = std::string(kTwoMessages) +
                  "BO_ 3000 C: 8 X\n"                                // 5: standard id above 0x7FF
                  " SG_ U : 0|8@1+ (1,0) [0|0] \"\" X\n"
                  " SG_ U : 8|8@1+ (1,0) [0|0] \"\" X\n"             // 7: duplicate signal
                  "BO_ 100 A2: 8 X\n"                                // 8: duplicate id
                  "VAL_ 999 S 1 \"x\";\n"                            // 9: unknown message
                  "CM_ SG_ 100 NOPE \"x\";\n"                        // 10: unknown signal
                  "BA_DEF_ BO_ \"Weird\" BLOB 1 2;\n"                // 11: unknown attribute type
                  "BA_ \"GenMsgCycleTime\" BO_ 555 10;\n"            // 12: attribute on unknown message
                  "VAL_ 100 S 1 \"a\";\nVAL_ 100 S 2 \"b\";\n"       // 13, 14: value table given twice
                  "BO_ 1073743490 E: 8 X\n"                         // 15: bit 30 set (0x40000682)
                  "BA_ \"GenSigStartValue\" SG_ 100 Nope 1;\n";      // 16: attribute on unknown signal
  Database db = parse_dbc(t, "q.dbc");
  EXPECT_NE(warning(db, DbcWarningKind::StandardIdAbove7FF, 5), nullptr);
  EXPECT_TRUE(db.find("C")->extended);
  EXPECT_NE(warning(db, DbcWarningKind::Duplicate, 7), nullptr);
  EXPECT_EQ(db.find("C")->signals.size(), 1u);
  EXPECT_NE(warning(db, DbcWarningKind::Duplicate, 8), nullptr);
  EXPECT_EQ(db.find(100, false)->name, "A");  // the first wins
  EXPECT_NE(warning(db, DbcWarningKind::UnknownReference, 9), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::UnknownReference, 10), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::UnknownAttributeType, 11), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::UnknownReference, 12), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::Duplicate, 14), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::ReservedIdBits, 15), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::UnknownReference, 16), nullptr);
  EXPECT_EQ(db.find(0x682, false)->name, "E");
  ASSERT_NE(db.find("A")->signals[0].choice(2), nullptr);  // the last VAL_ wins
  EXPECT_EQ(db.find("A")->signals[0].choice(1), nullptr);
  expect_strict_refuses(t, 5);
}

TEST(DbcLenient, BrokenMessageSkipsItsSignalsNotTheFile) {
  std::string t = std::string(kTwoMessages) +
                  "BO_ 300 Broken: eight X\n"                        // 5: no size
                  " SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" X\n"        // 6: belongs to Broken
                  "BO_ 400 D: 8 X\n"
                  " SG_ V : 0|8@1+ (1,0) [0|0] \"\" X\n"
                  " SG_ W : 8|8@9+ (1,0) [0|0] \"\" X\n"             // 9: broken signal
                  " SG_ Z : 16|8@1+ (1,0) [0|0] \"\" X\n";
  Database db = parse_dbc(t, "q.dbc");
  ASSERT_EQ(db.messages.size(), 3u);
  EXPECT_EQ(db.find("B")->signals.size(), 1u);  // Orphan is not attached to the message before
  EXPECT_EQ(db.find("D")->signals.size(), 2u);  // V and Z; W skipped
  EXPECT_NE(warning(db, DbcWarningKind::SkippedStatement, 5), nullptr);
  EXPECT_NE(warning(db, DbcWarningKind::SkippedStatement, 9), nullptr);
  EXPECT_NE(db.skipped_note("Broken").find("q.dbc:5 was skipped"), std::string::npos) << db.skipped_note("Broken");
  EXPECT_NE(db.skipped_note("Broken", "Orphan").find("q.dbc:5"), std::string::npos);
  EXPECT_NE(db.skipped_note("D", "W").find("q.dbc:9 was skipped: "), std::string::npos) << db.skipped_note("D", "W");
  EXPECT_EQ(db.skipped_note("D", "V"), "");
  expect_strict_refuses(t, 5);
}

TEST(DbcLenient, FormatConstructsAreNoQuirks) {
  // CRLF, node lists over several lines, CAN FD sizes, extended multiplexing, value types, signal
  // groups and environment variables are part of the format: no warning, and --strict reads them.
  std::string t =
      "VERSION \"\"\r\n"
      "BU_:\r\n\tECU\r\n\tGW\r\n"
      "BO_ 2147484000 Fd: 64 ECU\r\n"
      " SG_ Mux M : 0|8@1+ (1,0) [0|0] \"\" GW\r\n"
      " SG_ F m1 : 8|32@1- (1,0) [0|0] \"\" GW\r\n"
      " SG_ G m2 : 504|8@1+ (1,0) [0|0] \"\" GW\r\n"
      "EV_ Env: 0 [0|10] \"\" 0 1 DUMMY_NODE_VECTOR0 Vector__XXX;\r\n"
      "SIG_GROUP_ 2147484000 Grp 1 : F G;\r\n"
      "SIG_VALTYPE_ 2147484000 F : 1;\r\n"
      "SG_MUL_VAL_ 2147484000 G Mux 2-4, 7-7;\r\n";
  Database db = parse_dbc(t, "q.dbc", DbcOptions{true});
  EXPECT_EQ(db.nodes, (std::vector<std::string>{"ECU", "GW"}));
  const DbcMessage* m = db.find("Fd");
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->size, 64);
  EXPECT_EQ(m->signals[1].value_type, ValueType::Float32);
  EXPECT_EQ(m->signals[2].mux_ranges.size(), 2u);
}

TEST(DbcLenient, MappingOnASkippedSignalNamesItsDefinition) {
  std::string t = std::string(kTwoMessages) + " SG_ Broken : 8|8@7+ (1,0) [0|0] \"\" X\n";  // line 5
  Database db = parse_dbc(t, "q.dbc");
  try {
    Model m(&db, parse_mapping("[Vehicle.Speed]\nsource = B.Broken\ntimeout = none\n", "v.map"));
    FAIL() << "a mapping on a skipped signal was accepted";
  } catch (const MappingError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("v.map:1:"), std::string::npos) << w;
    EXPECT_NE(w.find("its definition at q.dbc:5 was skipped: "), std::string::npos) << w;
    EXPECT_NE(w.find("byte order"), std::string::npos) << w;
  }
}

TEST(DbcLenient, CheckDbcLintReportAndStrictExitCodes) {
  const std::string path = ::testing::TempDir() + "/meter_lint_quirks.dbc";
  {
    std::ofstream f(path);
    f << kTwoMessages << "CM_ SG_ 100 \"no signal\";\nVAL_ 200 T 1 \"one\"\nVAL_ 100 S 1 \"one\";\n";
  }
  std::ostringstream out, err;
  EXPECT_EQ(check_dbc_command(path, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("lint: 2 message(s), 2 signal(s), 0 multiplexed message(s), 2 warning(s)\n"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("  missing-semicolon: 1\n  unnamed-comment: 1\n"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find(path + ":6: warning [missing-semicolon]: VAL_ has no ';'"), std::string::npos) << out.str();
  std::ostringstream sout, serr;
  EXPECT_EQ(check_dbc_command(path, sout, serr, true), 1);
  EXPECT_NE(serr.str().find(path + ":5: error [unnamed-comment]"), std::string::npos) << serr.str();
  // decode --strict refuses the file before reading the log (which does not exist).
  std::ostringstream dout, derr;
  EXPECT_EQ(decode_command(path, "/nonexistent.log", "", dout, derr, true), 1);
  EXPECT_NE(derr.str().find("2 problem(s) refused by --strict"), std::string::npos) << derr.str();
  // Lenient decode names the warnings in one line and goes on (to the missing log here).
  std::ostringstream lout, lerr;
  EXPECT_EQ(decode_command(path, "/nonexistent.log", "", lout, lerr), 1);
  EXPECT_NE(lerr.str().find(": 2 DBC warning(s), first " + path + ":5: [unnamed-comment]"), std::string::npos) << lerr.str();
  EXPECT_NE(lerr.str().find("/nonexistent.log"), std::string::npos) << lerr.str();
  std::ostringstream mout, merr;
  EXPECT_EQ(check_dbc_command("/nonexistent/x.dbc", mout, merr), 1);
  std::remove(path.c_str());
}

TEST(DbcLenient, TextThatIsNotUtf8IsReadAsWindows1252WithAWarningAtItsFirstLine) {
  // A CANdb++ file saved on Windows: the degree sign is the single byte 0xB0 on line 3.
  const std::string text = std::string(kTwoMessages) + "CM_ SG_ 100 S \"temperature in \xB0" "C\";\n";
  const Database db = parse_dbc(text, "q.dbc");
  const DbcWarning* w = warning(db, DbcWarningKind::NotUtf8, 5);
  ASSERT_NE(w, nullptr);
  EXPECT_NE(w->text.find("Windows-1252"), std::string::npos) << w->text;
  EXPECT_EQ(db.find("A")->signals[0].comment, "temperature in \xC2\xB0" "C");
  expect_strict_refuses(text, 5);
  EXPECT_EQ(warning(parse_dbc(kTwoMessages, "q.dbc"), DbcWarningKind::NotUtf8, 1), nullptr);  // UTF-8: nothing
}

// Found by the dbc fuzz target (UBSan: a double outside an int's range converted to int): a cycle
// time an int cannot hold, as a message's attribute or as the default, is no cycle time; the
// message keeps none and the line is named, the rest of the file is read.
// An ENUM attribute's value given as an index far outside its values (a fuzzed 1e300, or a
// negative one) is no value: no frame format is taken from it and nothing is converted out of range.
TEST(DbcLenient, FuzzEnumIndexOutsideItsValuesIsIgnored) {
  const std::string def = "BA_DEF_ BO_ \"VFrameFormat\" ENUM \"StandardCAN\",\"ExtendedCAN\",\"reserved\",\"J1939PG\",\"StandardCAN_FD\";\n";
  Database db = parse_dbc(std::string(kTwoMessages) + def +
                              "BA_ \"VFrameFormat\" BO_ 100 1e300;\n"
                              "BA_ \"VFrameFormat\" BO_ 200 -7;\n",
                          "q.dbc");
  for (const char* name : {"A", "B"}) {
    EXPECT_FALSE(db.find(name)->fd) << name;
    EXPECT_FALSE(db.find(name)->j1939) << name;
  }
  // An index inside the list still names its value.
  Database ok = parse_dbc(std::string(kTwoMessages) + def + "BA_ \"VFrameFormat\" BO_ 100 4;\nBA_ \"VFrameFormat\" BO_ 200 1;\n", "q.dbc");
  EXPECT_TRUE(ok.find("A")->fd);   // StandardCAN_FD
  EXPECT_FALSE(ok.find("B")->fd);  // ExtendedCAN
}

TEST(DbcLenient, FuzzCycleTimeBeyondAnIntIsIgnoredNamingItsLine) {
  std::string t = std::string(kTwoMessages) +
                  "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 65535;\n"   // 5
                  "BA_DEF_DEF_ \"GenMsgCycleTime\" 7777777777777777777777;\n"  // 6: the default
                  "BA_ \"GenMsgCycleTime\" BO_ 200 1e300;\n";        // 7: one message's
  Database db = parse_dbc(t, "q.dbc");
  EXPECT_FALSE(db.find("A")->cycle_time_ms.has_value());
  EXPECT_FALSE(db.find("B")->cycle_time_ms.has_value());
  const DbcWarning* d = warning(db, DbcWarningKind::SkippedStatement, 6);
  ASSERT_NE(d, nullptr);
  EXPECT_NE(d->text.find("GenMsgCycleTime"), std::string::npos) << d->text;
  EXPECT_NE(warning(db, DbcWarningKind::SkippedStatement, 7), nullptr);
  // An ordinary cycle time still reads.
  Database ok = parse_dbc(std::string(kTwoMessages) + "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 65535;\n"
                                                    "BA_ \"GenMsgCycleTime\" BO_ 100 20;\n", "q.dbc");
  EXPECT_EQ(ok.find("A")->cycle_time_ms, 20);
}
