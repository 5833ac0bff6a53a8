// Times with units and render sizes, and the errors naming the flag.
#include "meter/runner/option_units.hpp"

#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

std::string time_error(const std::string& text) {
  try {
    parse_time(text, "--dump-at");
  } catch (const ViewError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string size_error(const std::string& text) {
  try {
    parse_size(text);
  } catch (const ViewError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ParseTime, SecondsMillisecondsAndBareNumbers) {
  EXPECT_DOUBLE_EQ(parse_time("12.5s", "--at"), 12.5);
  EXPECT_DOUBLE_EQ(parse_time("12.5", "--at"), 12.5);
  EXPECT_DOUBLE_EQ(parse_time("250ms", "--at"), 0.25);
  EXPECT_DOUBLE_EQ(parse_time("2520ms", "--at"), 2.52);
  EXPECT_DOUBLE_EQ(parse_time("0", "--at"), 0.0);
  EXPECT_DOUBLE_EQ(parse_time("1e1s", "--at"), 10.0);
}

TEST(ParseTime, ErrorsNameTheFlag) {
  EXPECT_EQ(time_error("2x"), "--dump-at: unknown unit \"x\" (use s or ms)");
  EXPECT_EQ(time_error("2 s"), "--dump-at: unknown unit \" s\" (use s or ms)");
  EXPECT_EQ(time_error("soon"), "--dump-at: \"soon\" is not a time (examples: 12.5s, 250ms)");
  EXPECT_EQ(time_error(""), "--dump-at: \"\" is not a time (examples: 12.5s, 250ms)");
  EXPECT_EQ(time_error("-1s"), "--dump-at: time must be finite and >= 0");
  EXPECT_EQ(time_error("nan"), "--dump-at: time must be finite and >= 0");
  EXPECT_EQ(time_error("inf"), "--dump-at: time must be finite and >= 0");
}

TEST(ParseSize, WidthByHeight) {
  EXPECT_EQ(parse_size("1280x480"), std::make_pair(1280, 480));
  EXPECT_EQ(parse_size("640X240"), std::make_pair(640, 240));
  EXPECT_EQ(parse_size("16x8192"), std::make_pair(16, 8192));
}

TEST(ParseSize, RejectsOtherShapesAndRanges) {
  for (const char* bad : {"1280", "1280x", "x480", "1280*480", "1280x480x", "15x480", "1280x8193", "-640x240", ""}) {
    EXPECT_EQ(size_error(bad), std::string("--size: expected WxH with 16..8192 each, got \"") + bad + "\"") << bad;
  }
}

}  // namespace
}  // namespace meter::runner
