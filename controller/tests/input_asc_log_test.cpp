#include <gtest/gtest.h>

#include <sstream>

#include "meter/controller/input/asc_log.hpp"
#include "meter/controller/input/asc_log_writer.hpp"
#include "meter/controller/input/log_fields.hpp"

using namespace meter::controller;

namespace {
constexpr std::int64_t kMs = 1000000;
}  // namespace

TEST(AscLog, DecimalBaseRelativeTimesChannelsAndEveryFrameKind) {
  const ParsedLog log = parse_asc_log(
      "date Mon Sep 13 10:20:30.250 am 2021\n"
      "base dec  timestamps relative\n"
      "no internal events logged\n"
      "// version 13.0.0\n"
      "Begin TriggerBlock Mon Sep 13 10:20:30.250 am 2021\n"
      "   0.000000 Start of measurement\n"
      "   0.001000 1  100             Rx   d 2 1 255\n"
      "   0.000500 2  1000x           Tx   d 8 1 2 3 4 5 6 7 8  Length = 111 BitCount = 64 ID = 1000x\n"
      "   0.000100 1  ErrorFrame\n"
      "   0.000100 2  200             Rx   r 4\n"
      "   0.000100 CANFD   1 Rx 300  EngineData 1 0 9 12 1 2 3 4 5 6 7 8 9 10 11 12 0 0 3000 0 0 0 0 0\n"
      "   0.000100 CANFD   2 Rx 301 0 1 8 8 1 2 3 4 5 6 7 8 0 0 0 0 0 0 0 0\n"
      "   0.000100 1  Statistic: D 0 R 0 XD 0 XR 0 E 0 O 0 B 0.00%\n"
      "End TriggerBlock\n");
  ASSERT_TRUE(log.bad_lines.empty()) << log.bad_lines.front().line << ": " << log.bad_lines.front().why;
  EXPECT_EQ(log.skipped, 2u);  // the start of measurement and the statistics
  ASSERT_EQ(log.frames.size(), 6u);
  const std::int64_t start = *local_time_ns(2021, 9, 13, 10, 20, 30, 250 * kMs);
  const CanFrame& a = log.frames[0];
  EXPECT_EQ(a.timestamp_ns, start + kMs);
  EXPECT_EQ(a.id, 100u);
  EXPECT_EQ(a.channel, 1);
  EXPECT_EQ(a.len, 2);
  EXPECT_EQ(a.data[1], 255);
  const CanFrame& b = log.frames[1];
  EXPECT_EQ(b.timestamp_ns, start + kMs + kMs / 2);  // relative: from the event before
  EXPECT_TRUE(b.extended);
  EXPECT_EQ(b.id, 1000u);
  EXPECT_EQ(b.channel, 2);
  EXPECT_EQ(b.data[7], 8);
  EXPECT_TRUE(log.frames[2].error);
  EXPECT_TRUE(log.frames[3].rtr);
  EXPECT_EQ(log.frames[3].len, 4);
  const CanFrame& fd = log.frames[4];
  EXPECT_TRUE(fd.fd);
  EXPECT_EQ(fd.fd_flags, kCanFdBrs);
  EXPECT_EQ(fd.len, 12);
  EXPECT_EQ(fd.data[11], 12);
  EXPECT_EQ(fd.id, 300u);
  EXPECT_FALSE(log.frames[5].fd);  // EDL clear in the flags: a classic frame in CANFD form
  EXPECT_EQ(log.frames[5].channel, 2);
}

TEST(AscLog, AbsoluteTimesWithoutADateStartAtZeroAndBadLinesSayWhatWasExpected) {
  const ParsedLog log = parse_asc_log(
      "base hex  timestamps absolute\n"
      "   1.500000 1  7FF   Rx   d 1 AB\n"
      "Hello world\n"
      "   1.600000 1  800   Rx   d 1 AB\n"
      "   1.700000 1  123   Rx   d 2 AB\n"
      "   1.800000 Foo bar\n"
      "   1.900000 1  123   Rx   d 1 AB CD\n"
      "   2.000000 1  1FFFFFFFx Tx d F 1 2 3 4 5 6 7 8\n");
  ASSERT_EQ(log.frames.size(), 2u);
  EXPECT_EQ(log.frames[0].timestamp_ns, 1500 * kMs);
  EXPECT_EQ(log.frames[1].len, 8);
  EXPECT_EQ(log.frames[1].len8_dlc, 15);
  ASSERT_EQ(log.bad_lines.size(), 5u);
  EXPECT_EQ(log.bad_lines[0].line, 3u);
  EXPECT_NE(log.bad_lines[0].why.find("unknown keyword 'Hello'"), std::string::npos) << log.bad_lines[0].why;
  EXPECT_NE(log.bad_lines[1].why.find("up to 7FF"), std::string::npos) << log.bad_lines[1].why;
  EXPECT_NE(log.bad_lines[2].why.find("expected 2 byte(s), got 1"), std::string::npos) << log.bad_lines[2].why;
  EXPECT_NE(log.bad_lines[3].why.find("unknown event 'Foo'"), std::string::npos) << log.bad_lines[3].why;
  EXPECT_NE(log.bad_lines[4].why.find("unexpected 'CD'"), std::string::npos) << log.bad_lines[4].why;
}

TEST(AscLog, TheWriterWritesWhatTheReaderReadsBack) {
  ParsedLog log;
  CanFrame f;
  f.timestamp_ns = 1631416514717133000LL;
  f.id = 0x123;
  f.len = 3;
  f.data = {1, 2, 3};
  f.channel = 2;
  log.frames.push_back(f);
  CanFrame fd = f;
  fd.timestamp_ns += 1000;
  fd.extended = true;
  fd.id = 0x1ABCDEF0;
  fd.fd = true;
  fd.fd_flags = kCanFdBrs | kCanFdEsi;
  fd.len = 64;
  fd.data.fill(0xA5);
  log.frames.push_back(fd);
  CanFrame r = f;
  r.timestamp_ns += 2000;
  r.rtr = true;
  r.len = 4;
  log.frames.push_back(r);
  CanFrame e;
  e.timestamp_ns = f.timestamp_ns + 3000;
  e.error = true;
  e.channel = 1;
  log.frames.push_back(e);
  std::ostringstream out;
  ParsedLogSource frames(log);
  write_asc_log(frames, out, [](std::size_t) {});
  const ParsedLog back = parse_asc_log(out.str());
  ASSERT_TRUE(back.bad_lines.empty()) << back.bad_lines.front().why << "\n" << out.str();
  ASSERT_EQ(back.frames.size(), 4u) << out.str();
  for (std::size_t i = 0; i < 4; ++i) {
    const CanFrame &a = log.frames[i], &b = back.frames[i];
    EXPECT_EQ(a.timestamp_ns, b.timestamp_ns) << i;
    EXPECT_EQ(a.id, b.id) << i;
    EXPECT_EQ(a.extended, b.extended) << i;
    EXPECT_EQ(a.rtr, b.rtr) << i;
    EXPECT_EQ(a.error, b.error) << i;
    EXPECT_EQ(a.fd, b.fd) << i;
    EXPECT_EQ(a.fd_flags, b.fd_flags) << i;
    EXPECT_EQ(a.len, b.len) << i;
    EXPECT_EQ(a.channel, b.channel) << i;
    if (!a.rtr) {
      EXPECT_EQ(a.data, b.data) << i;
    }
  }
  EXPECT_TRUE(sniff_asc_log(out.str()));
}
