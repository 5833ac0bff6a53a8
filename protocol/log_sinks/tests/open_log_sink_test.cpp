#include <gtest/gtest.h>

#include <stdexcept>

#include "meter/log_sinks/open_log_sink.hpp"

using namespace meter::log_sinks;

TEST(SinkKind, Names) {
  EXPECT_EQ(parse_sink_kind("journal"), SinkKind::Journal);
  EXPECT_EQ(parse_sink_kind("dlt"), SinkKind::Dlt);
  EXPECT_EQ(parse_sink_kind("json"), SinkKind::Json);
  EXPECT_EQ(parse_sink_kind("text"), SinkKind::Text);
  EXPECT_FALSE(parse_sink_kind("syslog"));
}

TEST(SinkKind, TheJournalOnlyWhenJournalStreamNamesStderr) {
  EXPECT_EQ(default_sink_kind("2049:131", true, 2049, 131), SinkKind::Journal);
  EXPECT_EQ(default_sink_kind(nullptr, true, 2049, 131), SinkKind::Text);     // not a service
  EXPECT_EQ(default_sink_kind("2049:131", true, 2049, 132), SinkKind::Text);  // stderr redirected since
  EXPECT_EQ(default_sink_kind("2049:131", false, 2049, 131), SinkKind::Text); // stderr closed
  for (const char* bad : {"", "2049", "2049:", ":131", "2049:131x", "x:131", "2049:131:7", "-1:131"})
    EXPECT_EQ(default_sink_kind(bad, true, 2049, 131), SinkKind::Text) << bad;
}

TEST(ProcessLogging, BadOptionsNameTheOptionAndItsValues) {
  try {
    configure_process_logging("meter-test", "text", "loud");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--log-level: expected error, warning, info or debug, got 'loud'");
  }
  try {
    configure_process_logging("meter-test", "syslog", "");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--log: expected text, json, journal or dlt, got 'syslog'");
  }
}
