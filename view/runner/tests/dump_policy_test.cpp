// Which live frames are dumped: every Nth, the first at or after each time, on request, the last.
#include "meter/runner/dump_policy.hpp"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

namespace meter::runner {
namespace {

// The frames dumped over `frames` frames at `fps`, with requests before the listed frames.
std::vector<std::uint64_t> dumped(DumpPolicy policy, int frames, double fps, std::vector<std::uint64_t> requests = {}) {
  std::vector<std::uint64_t> out;
  for (std::uint64_t f = 0; f < static_cast<std::uint64_t>(frames); ++f) {
    const bool requested = std::find(requests.begin(), requests.end(), f) != requests.end();
    if (policy.decide(f, static_cast<double>(f) / fps, requested).write) out.push_back(f);
  }
  return out;
}

TEST(DumpPolicy, NothingByDefault) {
  EXPECT_TRUE(dumped(DumpPolicy(0, {}, false), 50, 10.0).empty());
}

TEST(DumpPolicy, EveryNthFrameFromTheFirst) {
  EXPECT_EQ(dumped(DumpPolicy(3, {}, false), 10, 10.0), (std::vector<std::uint64_t>{0, 3, 6, 9}));
  EXPECT_EQ(dumped(DumpPolicy(1, {}, false), 3, 10.0), (std::vector<std::uint64_t>{0, 1, 2}));
}

TEST(DumpPolicy, TheFirstFrameAtOrAfterEachTime) {
  // 10 fps: frame n at n/10 s. 0.5 s is frame 5 exactly; 0.55 s is served by frame 6.
  EXPECT_EQ(dumped(DumpPolicy(0, {0.55, 0.5, 2.0}, false), 30, 10.0), (std::vector<std::uint64_t>{5, 6, 20}));
}

TEST(DumpPolicy, TimesInOneFrameGapShareOneDump) {
  EXPECT_EQ(dumped(DumpPolicy(0, {0.51, 0.52, 0.59}, false), 10, 10.0), (std::vector<std::uint64_t>{6}));
}

TEST(DumpPolicy, TimesAlreadyPastAtTheFirstFrameAreServedByIt) {
  DumpPolicy p(0, {0.0, 0.1}, false);
  EXPECT_TRUE(p.decide(0, 0.3, false).write);
  EXPECT_FALSE(p.decide(1, 0.4, false).write) << "used up";
}

TEST(DumpPolicy, TimesAfterTheLastFrameAreNeverServed) {
  EXPECT_TRUE(dumped(DumpPolicy(0, {10.0}, false), 20, 10.0).empty());
}

TEST(DumpPolicy, ARequestDumpsThatFrame) {
  EXPECT_EQ(dumped(DumpPolicy(0, {}, false), 10, 10.0, {4, 7}), (std::vector<std::uint64_t>{4, 7}));
  EXPECT_EQ(dumped(DumpPolicy(5, {0.2}, false), 10, 10.0, {5, 8}), (std::vector<std::uint64_t>{0, 2, 5, 8}))
      << "a request on a frame dumped anyway is one dump";
}

TEST(DumpPolicy, TheLastFrameOnExitOnlyWhenAskedAndAFrameExists) {
  EXPECT_TRUE(DumpPolicy(0, {}, true).dump_on_exit(12));
  EXPECT_FALSE(DumpPolicy(0, {}, true).dump_on_exit(0));
  EXPECT_FALSE(DumpPolicy(0, {}, false).dump_on_exit(12));
}

}  // namespace
}  // namespace meter::runner
