// Complexity of the controller's readers of outside input: a 10 MB DBC and a 1-million-line
// candump log parse in time linear in their size (bound and method: tests/support/linear_scaling.hpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <iostream>
#include <string>

#include "linear_scaling.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/candump_log.hpp"

using namespace meter::controller;
using meter::test::kLinearRatioBound;
using meter::test::kScaleFactor;

namespace {

// A DBC of `messages` 29-bit messages, each with 8 signals, a comment per message and signal,
// a value table, a cycle time: about 1 KB per message, every section the parser resolves.
std::string generated_dbc(int messages) {
  std::string head = "VERSION \"generated\"\n\nNS_ :\n\tCM_\n\tBA_DEF_\n\tBA_\n\tVAL_\n\nBS_:\n\nBU_: ECU ICL\n\n";
  std::string body, tail;
  tail += "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 65535;\nBA_DEF_DEF_ \"GenMsgCycleTime\" 100;\n";
  char line[256];
  for (int m = 0; m < messages; ++m) {
    const unsigned id = 0x80000000u | static_cast<unsigned>(0x100000 + m);
    std::snprintf(line, sizeof line, "BO_ %u MSG_%d: 8 ECU\n", id, m);
    body += line;
    for (int s = 0; s < 8; ++s) {
      std::snprintf(line, sizeof line, " SG_ Sig%d_%d : %d|8@1+ (0.5,-10) [-10|117.5] \"km/h\" ICL\n", m, s, s * 8);
      body += line;
      std::snprintf(line, sizeof line, "CM_ SG_ %u Sig%d_%d \"signal %d of message %d\";\n", id, m, s, s, m);
      tail += line;
    }
    body += "\n";
    std::snprintf(line, sizeof line, "CM_ BO_ %u \"message %d\";\nBA_ \"GenMsgCycleTime\" BO_ %u %d;\n", id, m, id, 10 + m % 90);
    tail += line;
    std::snprintf(line, sizeof line, "VAL_ %u Sig%d_0 0 \"off\" 1 \"on\" 2 \"error\" 3 \"not available\";\n", id, m);
    tail += line;
  }
  return head + body + tail;
}

// `lines` candump -L lines cycling through classic, extended, remote and CAN FD frames.
std::string generated_log(int lines) {
  std::string text;
  text.reserve(static_cast<std::size_t>(lines) * 48);
  char line[128];
  for (int i = 0; i < lines; ++i) {
    const long long us = 1631416514000000LL + i * 250LL;
    const char* frame = nullptr;
    switch (i % 4) {
      case 0: frame = "0D2#0000FFFF10000000"; break;
      case 1: frame = "12345678#DEADBEEF"; break;
      case 2: frame = "123#R"; break;
      default: frame = "1A0##1112233445566778899AABBCC"; break;
    }
    std::snprintf(line, sizeof line, "(%lld.%06lld) can0 %s\n", us / 1000000, us % 1000000, frame);
    text += line;
  }
  return text;
}

}  // namespace

TEST(InputComplexity, TenMegabyteDbcParsesInLinearTime) {
  const std::string large = generated_dbc(10000);
  const std::string small = generated_dbc(1000);
  ASSERT_GE(large.size(), 10u * 1000 * 1000);  // the issue's 10 MB
  ASSERT_EQ(parse_dbc(large).messages.size(), 10000u);
  const double ratio = meter::test::scaling_ratio([&] { (void)parse_dbc(small); }, [&] { (void)parse_dbc(large); });
  std::cout << "10 MB DBC: " << ratio << "x the time of 1 MB\n";
  EXPECT_LT(ratio, kLinearRatioBound) << kScaleFactor << "x the DBC took " << ratio << "x the time";
}

TEST(InputComplexity, MillionLineCandumpLogParsesInLinearTime) {
  const std::string large = generated_log(1000000);
  const std::string small = generated_log(100000);
  const ParsedLog parsed = parse_candump_log(large);
  ASSERT_EQ(parsed.frames.size(), 1000000u);
  ASSERT_TRUE(parsed.bad_lines.empty()) << parsed.bad_lines.front().why;
  const double ratio = meter::test::scaling_ratio([&] { (void)parse_candump_log(small); },
                                                  [&] { (void)parse_candump_log(large); });
  std::cout << "1M-line log: " << ratio << "x the time of 100k lines\n";
  EXPECT_LT(ratio, kLinearRatioBound) << kScaleFactor << "x the log took " << ratio << "x the time";
}
