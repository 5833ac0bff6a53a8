#include <gtest/gtest.h>

#include <sstream>

#include "meter/protocol/log/logger.hpp"

using namespace meter::protocol;

namespace {

class Capture : public RecordSink {
 public:
  explicit Capture(std::vector<LogRecord>& out) : out_(out) {}
  void write(const LogRecord& r) override { out_.push_back(r); }

 private:
  std::vector<LogRecord>& out_;
};

class Logging : public ::testing::Test {
 protected:
  void use(LogLevel threshold) { configure_logging("meter-test", threshold, std::make_unique<Capture>(records)); }
  void TearDown() override { configure_logging("", LogLevel::Info, nullptr); }
  std::vector<LogRecord> records;
};

}  // namespace

TEST_F(Logging, ThresholdDropsLessSevereRecords) {
  use(LogLevel::Warning);
  for (LogLevel l : {LogLevel::Debug, LogLevel::Info, LogLevel::Warning, LogLevel::Error}) {
    LogRecord r;
    r.level = l;
    r.message = std::string(to_string(l));
    write_log(r);
  }
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].message, "warning");
  EXPECT_EQ(records[1].message, "error");
  EXPECT_GT(records[0].time_ns, 0) << "stamped when written";
}

TEST_F(Logging, LineToALogStreamIsOneRecordWithItsFieldsAndPlace) {
  use(LogLevel::Info);
  LogStream err(LogLevel::Info, "run");
  LogLine(err, LogLevel::Warning, "health", {log_field("input", "can:vcan0")}) << "meter-controller: " << "bus " << 3 << "\n";
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].prefix, "meter-controller: ");
  EXPECT_EQ(records[0].message, "bus 3");
  EXPECT_EQ(records[0].component, "health");
  EXPECT_EQ(records[0].level, LogLevel::Warning);
  ASSERT_EQ(records[0].fields.size(), 1u);
  EXPECT_EQ(records[0].fields[0].value, "can:vcan0");
  EXPECT_TRUE(records[0].code_file.ends_with("logger_test.cpp"));
  EXPECT_GT(records[0].code_line, 0);
}

TEST_F(Logging, LineToAnyOtherStreamIsTodaysText) {
  use(LogLevel::Info);
  std::ostringstream err;
  LogLine(err, LogLevel::Error, "run") << "meter-controller: " << "cannot open x";
  EXPECT_EQ(err.str(), "meter-controller: cannot open x\n");
  EXPECT_TRUE(records.empty());
}

TEST_F(Logging, PlainWritesToALogStreamBecomeOneRecordPerLine) {
  use(LogLevel::Info);
  {
    LogStream err(LogLevel::Info, "view");
    err << "meter-view: 3 frames" << "\n" << "\n" << "trailing without newline";
    ASSERT_EQ(records.size(), 2u);
    EXPECT_EQ(records[0].message, "3 frames");
    EXPECT_EQ(records[0].component, "view");
    EXPECT_EQ(records[1].message, "") << "a blank line stays a line";
  }
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[2].message, "trailing without newline");
  EXPECT_EQ(records[2].prefix, "");
}

TEST_F(Logging, StreamRecordsAreFilteredToo) {
  use(LogLevel::Warning);
  LogStream err(LogLevel::Info, "view");
  err << "meter-view: summary\n";
  LogLine(err, LogLevel::Warning, "integrity") << "meter-view: fault";
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].message, "fault");
}
