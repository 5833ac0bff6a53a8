// The latency trace rows bench/latency reads, on CLOCK_REALTIME.
#include "meter/runner/latency_trace.hpp"

#include <thread>
#include <time.h>

#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

TEST(LatencyTrace, NowIsTheRealtimeClockInNanoseconds) {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  const std::int64_t before = static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
  const std::int64_t now = LatencyTrace::now();
  EXPECT_GE(now, before);
  EXPECT_LT(now - before, 1000000000LL);
}

TEST(LatencyTrace, RowsByEvent) {
  const auto file = testing::scratch_dir() / "trace.csv";
  const std::int64_t start = LatencyTrace::now();
  {
    LatencyTrace trace(file.string());
    trace.applied(123456789, 42);
    trace.frame(7, 1000, 2000);
    std::thread writer([&] { trace.png_written(7); });  // the PNG writer thread's row
    writer.join();
  }
  const auto lines = testing::read_lines(file);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "event,t_ns,a,b,c");

  const auto a = fields(lines[1]);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a[0], "a");
  EXPECT_GE(std::stoll(a[1]), start) << "stamped when applied";
  EXPECT_EQ(a[2], "123456789");
  EXPECT_EQ(a[3], "42");

  EXPECT_EQ(lines[2], "r,1000,7,2000");

  const auto w = fields(lines[3]);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0], "w");
  EXPECT_GE(std::stoll(w[1]), std::stoll(a[1]));
  EXPECT_EQ(w[2], "7");
}

TEST(LatencyTrace, NoPathNoFile) {
  LatencyTrace trace("");
  trace.applied(1, 2);
  trace.frame(1, 2, 3);
  trace.png_written(1);
  SUCCEED();
}

TEST(LatencyTrace, AnUnwritableFileIsNamed) {
  const auto file = (testing::scratch_dir() / "missing" / "trace.csv").string();
  try {
    LatencyTrace trace(file);
    FAIL() << "no error";
  } catch (const ViewError& e) {
    EXPECT_EQ(std::string(e.what()), file + ": cannot write the trace");
  }
}

}  // namespace
}  // namespace meter::runner
