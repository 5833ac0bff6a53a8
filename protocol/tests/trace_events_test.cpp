// Chrome trace-event objects: exact microsecond stamps from nanoseconds, escaped names, args.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "meter/protocol/trace_events.hpp"

using namespace meter::protocol;

TEST(TraceEvents, CompleteEventInMicrosecondsExactToTheNanosecond) {
  const TraceEvent e{"decode", "controller", 12'000'000'042LL, 12'000'123'499LL, 77, 1, {{"can_id", 291}}};
  EXPECT_EQ(format_trace_event(e),
            "{\"name\":\"decode\",\"cat\":\"controller\",\"ph\":\"X\",\"ts\":12000000.042,\"dur\":123.457,"
            "\"pid\":77,\"tid\":1,\"args\":{\"can_id\":291}}");
  // An end before the begin (a clock read out of order) is a zero-length slice, never negative.
  const TraceEvent back{"x", "c", 5'000, 4'000, 1, 2, {}};
  EXPECT_EQ(format_trace_event(back), "{\"name\":\"x\",\"cat\":\"c\",\"ph\":\"X\",\"ts\":5.000,\"dur\":0.000,\"pid\":1,\"tid\":2}");
}

TEST(TraceEvents, NamesAreEscapedJson) {
  EXPECT_EQ(json_quoted("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\u000a\\u0001\"");
  EXPECT_EQ(format_trace_name("thread_name", 3, 2, "png \"writer\""),
            "{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":3,\"tid\":2,\"args\":{\"name\":\"png \\\"writer\\\"\"}}");
}

TEST(TraceEvents, FileIsOneDocumentAndOffWithoutAPath) {
  const auto path = std::filesystem::temp_directory_path() / ("meter-trace-" + std::to_string(::getpid()) + ".json");
  {
    TraceEventFile f(path.string(), "meter-test");
    ASSERT_TRUE(f.on());
    f.thread_name(1, "main");
    f.complete("a", "t", 1000, 2000);
    f.complete("b", "t", 2000, 3500, 2, {{"n", -4}});
    EXPECT_TRUE(f.close());
    f.complete("late", "t", 1, 2);  // after close: dropped, the document stays whole
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  EXPECT_EQ(s.rfind("{\"displayTimeUnit\":\"ms\"", 0), 0u) << s;
  EXPECT_NE(s.find("\"process_name\""), std::string::npos);
  EXPECT_NE(s.find("\"name\":\"b\",\"cat\":\"t\",\"ph\":\"X\",\"ts\":2.000,\"dur\":1.500"), std::string::npos) << s;
  EXPECT_EQ(s.find("late"), std::string::npos);
  EXPECT_EQ(s.substr(s.size() - 4), "\n]}\n");
  std::filesystem::remove(path);

  TraceEventFile off("", "x");
  EXPECT_FALSE(off.on());
  off.complete("a", "t", 1, 2);
  EXPECT_TRUE(off.close());
  EXPECT_THROW(TraceEventFile("/nonexistent-dir/t.json", "x"), std::runtime_error);
}
