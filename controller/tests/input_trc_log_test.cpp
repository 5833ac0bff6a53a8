#include <gtest/gtest.h>

#include "meter/controller/input/trc_log.hpp"

using namespace meter::controller;

namespace {
constexpr std::int64_t kUs = 1000;

std::string why_of(const ParsedLog& log, std::size_t i) { return i < log.bad_lines.size() ? log.bad_lines[i].why : "(none)"; }
}  // namespace

TEST(TrcLog, Version10AndVersion11) {
  const ParsedLog v10 = parse_trc_log(
      ";##########\n"
      ";   Start time: 12.09.2021 05:15:14.717.0\n"
      "     1)      1841  0001  8  00 01 02 03 04 05 06 07\n"
      "     2)      1842  FFFFFFFF  4  00 00 00 08\n"
      "     3)      1843  1FFFFFFF  2  AA BB\n");
  ASSERT_TRUE(v10.bad_lines.empty()) << why_of(v10, 0);
  ASSERT_EQ(v10.frames.size(), 2u);
  EXPECT_EQ(v10.skipped, 1u);  // the bus status line
  EXPECT_EQ(v10.frames[0].timestamp_ns, 1841000 * kUs);
  EXPECT_EQ(v10.frames[0].channel, 1);
  EXPECT_TRUE(v10.frames[1].extended);
  EXPECT_TRUE(sniff_trc_log(";##\n     1)      1841  0001  8  00 01 02 03 04 05 06 07\n"));

  const ParsedLog v11 = parse_trc_log(
      ";$FILEVERSION=1.1\n"
      ";$STARTTIME=44451.5\n"
      "     1)      1841.0  Rx         0001  8  00 01 02 03 04 05 06 07\n"
      "     2)      1842.5  Tx     1FFFFFFF  4  AA BB CC DD\n"
      "     3)      1843.0  Rx         0002  2  RTR\n"
      "     4)      1844.0  Warng  FFFFFFFF  4  00 00 00 04  BUSLIGHT\n"
      "     5)      1845.0  Rx         0003  8  00 01 02\n");
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
  const ParsedLog v13 = parse_trc_log(
      ";$FILEVERSION=1.3\n"
      "     1)      1841.0 2  Rx         0001 -  2  00 01\n");
  ASSERT_EQ(v13.frames.size(), 1u) << why_of(v13, 0);
  EXPECT_EQ(v13.frames[0].channel, 2);

  const ParsedLog v20 = parse_trc_log(
      ";$FILEVERSION=2.0\n"
      ";$STARTTIME=44451.2188\n"
      ";$COLUMNS=N,O,T,I,d,l,D\n"
      "      1      1059.900 DT     0300 Rx 7  00 00 00 00 04 00 00\n"
      "      2      1060.000 FB     0400 Rx 12  01 02 03 04 05 06 07 08 09 0A 0B 0C\n"
      "      3      1061.000 RR     0500 Rx 2\n"
      "      4      1062.000 ST     Rx 00 00 00 08\n");
  ASSERT_TRUE(v20.bad_lines.empty()) << why_of(v20, 0);
  ASSERT_EQ(v20.frames.size(), 3u);
  EXPECT_EQ(v20.frames[0].timestamp_ns, 1059900 * kUs);
  EXPECT_EQ(v20.frames[0].len, 7);
  EXPECT_TRUE(v20.frames[1].fd);
  EXPECT_EQ(v20.frames[1].fd_flags, kCanFdBrs);
  EXPECT_EQ(v20.frames[1].len, 12);
  EXPECT_TRUE(v20.frames[2].rtr);
  EXPECT_EQ(v20.skipped, 1u);

  const ParsedLog v21 = parse_trc_log(
      ";$FILEVERSION=2.1\n"
      ";$COLUMNS=N,O,T,B,I,d,R,L,D\n"
      "      1         1.000 DT 2     0300 Rx -  8  00 01 02 03 04 05 06 07\n"
      "      2         2.001 BI 1 18FF0000 Tx -  9  01 02 03 04 05 06 07 08 09 0A 0B 0C\n"
      "      3         3.000 ER 1 Rx 01 02 03\n"
      "      4         4.000 XX 1     0300 Rx -  1  00\n"
      "      5         5.000 DT 1     0300 Rx -  8  00 01\n");
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

  const ParsedLog v30 = parse_trc_log(";$FILEVERSION=3.0\n");
  EXPECT_NE(why_of(v30, 0).find("file version: expected 1.0, 1.1, 1.2, 1.3, 2.0 or 2.1, got '3.0'"), std::string::npos);
}
