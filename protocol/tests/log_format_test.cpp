#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "meter/protocol/log/log_format.hpp"

using namespace meter::protocol;

namespace {

LogRecord sample() {
  LogRecord r;
  r.time_ns = 1796550601123456789;  // 2026-12-06T09:50:01.123456789Z
  r.level = LogLevel::Warning;
  r.component = "health";
  r.prefix = "meter-controller: ";
  r.message = "log:drive.log: bus error-passive";
  r.fields = {log_field("input", "log:drive.log"), log_field("frame", std::int64_t{42})};
  r.code_file = "controller/src/run/health_report.cpp";
  r.code_line = 27;
  return r;
}

}  // namespace

TEST(LogLevels, ParseAndFilter) {
  EXPECT_EQ(parse_log_level("error"), LogLevel::Error);
  EXPECT_EQ(parse_log_level("debug"), LogLevel::Debug);
  EXPECT_FALSE(parse_log_level("warn"));
  EXPECT_FALSE(parse_log_level("INFO"));
  EXPECT_EQ(to_string(LogLevel::Warning), "warning");
  EXPECT_TRUE(level_passes(LogLevel::Error, LogLevel::Warning));
  EXPECT_TRUE(level_passes(LogLevel::Warning, LogLevel::Warning));
  EXPECT_FALSE(level_passes(LogLevel::Info, LogLevel::Warning));
  EXPECT_FALSE(level_passes(LogLevel::Debug, LogLevel::Info));
}

TEST(LogRecordForms, PrefixIsSplitOffAsWritten) {
  std::string prefix, message;
  split_prefix("meter-view: integrity fault at frame 3", prefix, message);
  EXPECT_EQ(prefix, "meter-view: ");
  EXPECT_EQ(message, "integrity fault at frame 3");
  split_prefix("meter: note: skipped chunk", prefix, message);
  EXPECT_EQ(prefix, "meter: ");
  split_prefix("drive.dbc: 2 DBC warning(s)", prefix, message);
  EXPECT_EQ(prefix, "");
  EXPECT_EQ(message, "drive.dbc: 2 DBC warning(s)");
  split_prefix("meterology: x", prefix, message);  // a word starting with meter is no program
  EXPECT_EQ(prefix, "");
}

TEST(LogRecordForms, TextIsTodaysLine) {
  EXPECT_EQ(format_text(sample()), "meter-controller: log:drive.log: bus error-passive");
}

TEST(LogRecordForms, JsonHasTheRecordAndItsFields) {
  const std::string line = format_json(sample(), "meter-controller");
  EXPECT_EQ(line.find('\n'), std::string::npos);
  const auto j = nlohmann::json::parse(line);
  EXPECT_EQ(j["time"], "2026-12-06T09:50:01.123456Z");
  EXPECT_EQ(j["level"], "warning");
  EXPECT_EQ(j["program"], "meter-controller");
  EXPECT_EQ(j["component"], "health");
  EXPECT_EQ(j["message"], "log:drive.log: bus error-passive");
  EXPECT_EQ(j["input"], "log:drive.log");
  EXPECT_EQ(j["frame"], 42);
  EXPECT_EQ(line.rfind("{\"time\"", 0), 0u) << "the keys keep their order: time first";
}

TEST(LogRecordForms, JsonNeverLetsAFieldHideTheRecordNorDropsBadText) {
  LogRecord r = sample();
  r.fields = {log_field("level", "fake"), log_field("file", "a\"b\nc")};
  r.message = std::string("bad \xff byte");
  const auto j = nlohmann::json::parse(format_json(r, "meter-view"));
  EXPECT_EQ(j["level"], "warning");
  EXPECT_EQ(j["file"], "a\"b\nc");
  EXPECT_EQ(j["message"], "bad \xEF\xBF\xBD byte");
}

TEST(LogRecordForms, JournalFields) {
  const auto f = journal_fields(sample(), "meter-controller");
  const std::vector<std::string> expected{"MESSAGE=log:drive.log: bus error-passive",
                                          "PRIORITY=4",
                                          "SYSLOG_IDENTIFIER=meter-controller",
                                          "CODE_FILE=controller/src/run/health_report.cpp",
                                          "CODE_LINE=27",
                                          "METER_COMPONENT=health",
                                          "METER_INPUT=log:drive.log",
                                          "METER_FRAME=42"};
  EXPECT_EQ(f, expected);
  LogRecord r = sample();
  r.code_file.clear();
  r.level = LogLevel::Debug;
  r.fields = {log_field("can-id", "0x1A0")};
  const auto g = journal_fields(r, "meter-view");
  EXPECT_EQ(g[1], "PRIORITY=7");
  EXPECT_EQ(g.back(), "METER_CAN_ID=0x1A0");
  EXPECT_EQ(std::count_if(g.begin(), g.end(), [](const std::string& s) { return s.starts_with("CODE_"); }), 0);
  EXPECT_EQ(journal_priority(LogLevel::Error), 3);
  EXPECT_EQ(journal_priority(LogLevel::Info), 6);
}

TEST(LogRecordForms, DltIds) {
  const std::pair<const char*, const char*> apps[] = {
      {"meter-controller", "MCTL"}, {"meter-view", "MVEW"}, {"meter-linkplay", "MTOL"}};
  for (const auto& [program, id] : apps) EXPECT_EQ(dlt_app_id(program), id) << program;
  // the table's ids; an unknown component: its first four letters, upper case; none: MAIN
  const std::pair<const char*, const char*> contexts[] = {
      {"integrity", "INTG"}, {"e2e", "E2E"}, {"new-part", "NEW_"}, {"", "MAIN"}};
  for (const auto& [component, id] : contexts) EXPECT_EQ(dlt_context_id(component), id) << component;
}
