#include <gtest/gtest.h>

#include "meter/controller/input/candump_line.hpp"

using namespace meter::controller;

namespace {
CanFrame parse_ok(std::string_view line) {
  std::string why;
  auto r = parse_candump_line(line, &why);
  EXPECT_TRUE(r.has_value()) << line << ": " << why;
  return r ? r->frame : CanFrame{};
}
std::string parse_err(std::string_view line) {
  std::string why;
  auto r = parse_candump_line(line, &why);
  EXPECT_FALSE(r.has_value()) << line;
  return why;
}
}  // namespace

TEST(Candump, StandardFrame) {
  auto f = parse_ok("(1631416514.717133) can0 0D2#0000FFFF10000000");
  EXPECT_EQ(f.timestamp_ns, 1631416514717133000LL);
  EXPECT_EQ(f.id, 0xD2u);
  EXPECT_FALSE(f.extended);
  EXPECT_EQ(f.len, 8);
  EXPECT_EQ(f.data[2], 0xFF);
  EXPECT_EQ(f.data[4], 0x10);
}

TEST(Candump, ExtendedRtrDlcFdError) {
  auto e = parse_ok("(0000000001.000000) vcan0 1F334455#1122334455667788_B");
  EXPECT_TRUE(e.extended);
  EXPECT_EQ(e.id, 0x1F334455u);
  EXPECT_EQ(e.len8_dlc, 0xB);
  auto r = parse_ok("(1.5) can0 00000123#R3");
  EXPECT_TRUE(r.rtr);
  EXPECT_TRUE(r.extended);
  EXPECT_EQ(r.len, 3);
  EXPECT_EQ(r.timestamp_ns, 1500000000LL);
  auto r0 = parse_ok("(1.0) can0 123#R");
  EXPECT_TRUE(r0.rtr);
  EXPECT_EQ(r0.len, 0);
  auto r8 = parse_ok("(1.0) can0 333#R8_E");
  EXPECT_EQ(r8.len, 8);
  EXPECT_EQ(r8.len8_dlc, 0xE);
  auto fd = parse_ok("(1.0) can0 123##1112233445566778899AABBCC");
  EXPECT_TRUE(fd.fd);
  EXPECT_EQ(fd.fd_flags, 1);
  EXPECT_EQ(fd.len, 12);
  EXPECT_EQ(fd.data[11], 0xCC);
  auto fd0 = parse_ok("(1.0) can0 123##1");
  EXPECT_TRUE(fd0.fd);
  EXPECT_EQ(fd0.len, 0);
  auto dots = parse_ok("(1.0) can0 5A1#11.2233.44556677.88");
  EXPECT_EQ(dots.len, 8);
  EXPECT_EQ(dots.data[7], 0x88);
  auto empty = parse_ok("(1.0) can0 5AA#");
  EXPECT_EQ(empty.len, 0);
  auto err = parse_ok("(1.0) can0 20000080#0000000000000000");
  EXPECT_TRUE(err.error);
  EXPECT_EQ(err.id, 0x80u);
  auto dir = parse_ok("(1.0) can0 123#11 R\r\n");
  EXPECT_EQ(dir.len, 1);
}

TEST(Candump, BadLinesSayWhatWasExpected) {
  EXPECT_NE(parse_err("").find("timestamp"), std::string::npos);
  EXPECT_NE(parse_err("(1.0 can0 123#00").find(")"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 12#00").find("3 hex digits"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 800#00").find("0x7FF"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123#0").find("two hex digits"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123#001122334455667788").find("more than 8"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123##1001122334455667788").find("valid FD length"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123#0011_9").find("_9"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123#R9").find("0..8"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0 123#00 junk").find("direction"), std::string::npos);
  EXPECT_NE(parse_err("(x.0) can0 123#00").find("digits"), std::string::npos);
  EXPECT_NE(parse_err("(1.0) can0").find("frame"), std::string::npos);
}

TEST(Candump, FormatRoundTrips) {
  for (std::string_view line : {"(1631416514.717133) can0 0D2#0000FFFF10000000",
                                "(0000000001.500000) vcan0 00000123#R3", "(0000000001.000000) can0 333#R8_E",
                                "(0000000001.000000) can0 123##1112233445566778899AABBCC",
                                "(0000000001.000000) can0 1F334455#1122334455667788_B",
                                "(0000000002.000001) can0 20000080#0000000000000000",
                                "(0000000002.000001) can0 5AA#"}) {
    std::string why;
    auto r = parse_candump_line(line, &why);
    ASSERT_TRUE(r) << why;
    std::string out = format_candump_line(r->frame, r->interface);
    auto again = parse_candump_line(out, &why);
    ASSERT_TRUE(again) << out << ": " << why;
    EXPECT_EQ(format_candump_line(again->frame, again->interface), out);
    if (line[11] == '.') {
      EXPECT_EQ(out, line);
    }
  }
}

#include <chrono>
#include <thread>

#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_replay.hpp"

TEST(CandumpLog, BadLinesAreSkippedAndCountedWithLineNumbers) {
  ParsedLog log = parse_candump_log(
      "(1.000000) can0 123#00\n"
      "garbage\n"
      "\n"
      "(1.010000) can0 12#00\r\n"
      "(1.020000) can0 124#0102\r\n");
  EXPECT_EQ(log.frames.size(), 2u);
  ASSERT_EQ(log.bad_lines.size(), 2u);
  EXPECT_EQ(log.bad_lines[0].line, 2u);
  EXPECT_EQ(log.bad_lines[1].line, 4u);
  EXPECT_NE(log.bad_lines[1].why.find("3 hex digits"), std::string::npos);
  EXPECT_THROW(load_candump_log("/nonexistent.log"), std::runtime_error);
}

namespace {
struct Collect : InputSink {
  std::vector<std::int64_t> ts;
  void on_frame(const CanFrame& f) override { ts.push_back(f.timestamp_ns); }
  void on_value(std::string_view, double, bool, std::int64_t) override {}
};
std::string log_text(int n, int step_ms) {
  std::string s;
  for (int i = 0; i < n; ++i) {
    char b[64];
    std::snprintf(b, sizeof b, "(100.%06d) can0 123#%02X\n", i * step_ms * 1000, i & 0xFF);
    s += b;
  }
  return s;
}
}  // namespace

TEST(Replay, ModesParseAndFastIsDeterministic) {
  EXPECT_EQ(parse_replay("fast").mode, ReplayMode::Fast);
  EXPECT_EQ(parse_replay("realtime").mode, ReplayMode::Realtime);
  EXPECT_EQ(parse_replay("scale:2.5").scale, 2.5);
  EXPECT_THROW(parse_replay("scale:0"), std::invalid_argument);
  EXPECT_THROW(parse_replay("scale:x"), std::invalid_argument);
  EXPECT_THROW(parse_replay("slow"), std::invalid_argument);
  LogReplay r(parse_candump_log(log_text(50, 10)), parse_replay("fast"));
  Collect c;
  int polls = 0;
  std::vector<std::int64_t> clock;
  while (r.poll(c, std::chrono::milliseconds(10))) {
    ++polls;
    clock.push_back(r.now_ns());
  }
  EXPECT_EQ(c.ts.size(), 50u);
  EXPECT_EQ(polls, 48);  // 10 ms of simulated time per poll; the 49th delivers the last frame and ends
  EXPECT_EQ(clock.front(), 100010000000LL);
  for (std::size_t i = 1; i < c.ts.size(); ++i) EXPECT_LT(c.ts[i - 1], c.ts[i]);
}

// The tick that follows the end of a fast replay is stamped on the simulated clock, not on the
// simulated clock plus however long the machine took to get there: the same log gives the same
// model inputs (and the same --record file) on every run.
TEST(Replay, FastReplayEndsOnItsSimulatedClock) {
  LogReplay r(parse_candump_log(log_text(50, 10)), parse_replay("fast"));
  Collect c;
  while (r.poll(c, std::chrono::milliseconds(10))) {
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2));  // wall time passes before the next tick
  EXPECT_EQ(r.now_ns(), 100490000000LL);  // the 49th 10-ms step delivered the last frame
  EXPECT_FALSE(r.poll(c, std::chrono::milliseconds(40)));
  EXPECT_EQ(r.now_ns(), 100530000000LL);  // a silent bus: the clock runs on by the poll's wait
}

TEST(Replay, ScaledReplayKeepsTheRecordedTiming) {
  // 300 ms of log at scale 3 takes ~100 ms of wall time.
  LogReplay r(parse_candump_log(log_text(31, 10)), parse_replay("scale:3"));
  Collect c;
  auto t0 = std::chrono::steady_clock::now();
  while (r.poll(c, std::chrono::milliseconds(5))) {
  }
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(c.ts.size(), 31u);
  EXPECT_GE(wall, 0.095);
  EXPECT_LT(wall, 0.6);  // generous: the machine is shared
}

// After the last frame a replay is a silent bus: poll() keeps reporting the end without delivering
// anything, waits its timeout instead of returning at once (a loop polling it must not spin), and
// the clock runs on, so the model's timeouts expire.
TEST(Replay, AfterTheEndTheClockRunsOnAndPollWaits) {
  for (const char* mode : {"fast", "scale:4"}) {
    LogReplay r(parse_candump_log(log_text(5, 10)), parse_replay(mode));
    Collect c;
    while (r.poll(c, std::chrono::milliseconds(10))) {
    }
    ASSERT_EQ(c.ts.size(), 5u) << mode;
    const std::int64_t at_end = r.now_ns();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(r.poll(c, std::chrono::milliseconds(40))) << mode;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(c.ts.size(), 5u) << mode;
    // Five polls of 40 ms of input time: 200 ms of wall time in fast mode (its clock runs at wall
    // rate after the end), 50 ms at scale 4; the clock advanced by at least that input time.
    const double expected_wall = std::string(mode) == "fast" ? 0.2 : 0.05;
    EXPECT_GE(wall, expected_wall * 0.95) << mode;
    EXPECT_GE(r.now_ns() - at_end, 190000000) << mode;
  }
}

#include <random>

TEST(Candump, RandomLinesNeverCrashAndRoundTripWhenAccepted) {
  // Mutated real lines: either rejected with a reason, or accepted and then stable through
  // format -> parse (run under ASan/UBSan in CI).
  const std::string base[] = {"(1631416514.717133) can0 0D2#0000FFFF10000000", "(1.000000) vcan0 123##1112233445566778899AABBCC",
                              "(2.5) can0 00000123#R3", "(3.000001) can0 333#R8_E", "(4.0) can0 20000080#0011"};
  std::mt19937 rng(5);
  const char alphabet[] = "0123456789ABCDEFabcdef#R_.() \t-xZ";
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string t = base[rng() % 5];
    for (int k = 0; k < 1 + static_cast<int>(rng() % 3); ++k) {
      std::size_t pos = rng() % t.size();
      switch (rng() % 3) {
        case 0: t[pos] = alphabet[rng() % (sizeof alphabet - 1)]; break;
        case 1: t.erase(pos, 1); break;
        default: t.insert(pos, 1, alphabet[rng() % (sizeof alphabet - 1)]);
      }
      if (t.empty()) t = "(";
    }
    std::string why;
    auto r = parse_candump_line(t, &why);
    if (!r) {
      ASSERT_FALSE(why.empty()) << t;
      ++rejected;
      continue;
    }
    ++accepted;
    ASSERT_LE(r->frame.len, r->frame.fd ? 64 : 8) << t;
    std::string once = format_candump_line(r->frame, r->interface);
    auto again = parse_candump_line(once, &why);
    ASSERT_TRUE(again) << t << " -> " << once << ": " << why;
    ASSERT_EQ(format_candump_line(again->frame, again->interface), once);
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 100);
}
