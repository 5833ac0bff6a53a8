#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "meter/controller/input/trc_log.hpp"

using namespace meter::controller;

namespace {
constexpr std::int64_t kUs = 1000;

// A PEAK trace of controller/tests/data/logs/, one per file version.
ParsedLog read_sample(const std::string& name) {
  std::ifstream in(std::string(METER_SOURCE_DIR) + "/controller/tests/data/logs/" + name, std::ios::binary);
  EXPECT_TRUE(in.good()) << name;
  return read_trc_log(in);
}

std::string why_of(const ParsedLog& log, std::size_t i) { return i < log.bad_lines.size() ? log.bad_lines[i].why : "(none)"; }
}  // namespace

TEST(TrcLog, Version10AndVersion11) {
  const ParsedLog v10 = read_sample("v1.0.trc");
  ASSERT_TRUE(v10.bad_lines.empty()) << why_of(v10, 0);
  ASSERT_EQ(v10.frames.size(), 2u);
  EXPECT_EQ(v10.skipped, 1u);  // the bus status line
  EXPECT_EQ(v10.frames[0].timestamp_ns, 1841000 * kUs);
  EXPECT_EQ(v10.frames[0].channel, 1);
  EXPECT_TRUE(v10.frames[1].extended);
  EXPECT_TRUE(sniff_trc_log(";##\n     1)      1841  0001  8  00 01 02 03 04 05 06 07\n"));  // no version line

  const ParsedLog v11 = read_sample("v1.1.trc");
  ASSERT_EQ(v11.frames.size(), 3u);
  EXPECT_EQ(v11.frames[1].timestamp_ns, 1842500 * kUs);
  EXPECT_EQ(v11.frames[1].id, 0x1FFFFFFFu);
  EXPECT_TRUE(v11.frames[2].rtr);
  EXPECT_EQ(v11.frames[2].len, 2);
  EXPECT_EQ(v11.skipped, 1u);
  ASSERT_EQ(v11.bad_lines.size(), 1u);
  EXPECT_EQ(v11.bad_lines[0].line, 7u);
  EXPECT_NE(why_of(v11, 0).find("expected 13 columns (NOTILD with 8 data bytes), got 8"), std::string::npos) << why_of(v11, 0);
}

TEST(TrcLog, Version13And20And21WithTheirColumns) {
  const ParsedLog v13 = read_sample("v1.3.trc");
  ASSERT_EQ(v13.frames.size(), 1u) << why_of(v13, 0);
  EXPECT_EQ(v13.frames[0].channel, 2);

  const ParsedLog v20 = read_sample("v2.0.trc");
  ASSERT_TRUE(v20.bad_lines.empty()) << why_of(v20, 0);
  ASSERT_EQ(v20.frames.size(), 3u);
  EXPECT_EQ(v20.frames[0].timestamp_ns, 1059900 * kUs);
  EXPECT_EQ(v20.frames[0].len, 7);
  EXPECT_TRUE(v20.frames[1].fd);
  EXPECT_EQ(v20.frames[1].fd_flags, kCanFdBrs);
  EXPECT_EQ(v20.frames[1].len, 12);
  EXPECT_TRUE(v20.frames[2].rtr);
  EXPECT_EQ(v20.skipped, 1u);

  const ParsedLog v21 = read_sample("v2.1.trc");
  ASSERT_EQ(v21.frames.size(), 3u);
  EXPECT_EQ(v21.frames[0].channel, 2);
  EXPECT_EQ(v21.frames[1].timestamp_ns, 2001 * kUs);
  EXPECT_TRUE(v21.frames[1].extended);
  EXPECT_EQ(v21.frames[1].fd_flags, kCanFdBrs | kCanFdEsi);
  EXPECT_EQ(v21.frames[1].len, 12);  // DLC 9 of a CAN FD frame
  EXPECT_TRUE(v21.frames[2].error);
  ASSERT_EQ(v21.bad_lines.size(), 2u);
  EXPECT_NE(why_of(v21, 0).find("type: expected"), std::string::npos) << why_of(v21, 0);
  EXPECT_NE(why_of(v21, 1).find("expected 16 columns (NOTBIdRLD with 8 data bytes), got 10"), std::string::npos) << why_of(v21, 1);

  // Columns without a message number are read; columns without a length are refused (found by fuzzing).
  const ParsedLog cols = read_sample("columns.trc");
  ASSERT_EQ(cols.frames.size(), 1u) << why_of(cols, 0);
  EXPECT_EQ(cols.frames[0].len, 2);
  EXPECT_NE(why_of(cols, 0).find("columns: expected letters such as N,O,T,B,I,d,R,L,D with O, I and L (or l)"), std::string::npos);
  const ParsedLog v30 = read_sample("v3.0.trc");
  EXPECT_NE(why_of(v30, 0).find("file version: expected 1.0, 1.1, 1.2, 1.3, 2.0 or 2.1, got '3.0'"), std::string::npos);
}
