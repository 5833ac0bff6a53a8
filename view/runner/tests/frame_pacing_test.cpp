// The frame clock: period, the view's clock, no burst after a late frame, and the wait that
// services the link until the next frame is due.
#include "meter/view/frame_pacing.hpp"

#include <algorithm>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace meter::view {
namespace {

using Clock = FramePacer::Clock;
using std::chrono::milliseconds;

TEST(FramePacer, FramesFollowThePeriodOnTheViewsClock) {
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  FramePacer p(20.0, t0);
  EXPECT_EQ(p.period(), milliseconds(50));
  EXPECT_EQ(p.next_due(), t0) << "the first frame is due at once";

  auto f0 = p.begin_frame(t0 + milliseconds(2));
  EXPECT_NEAR(f0.t, 0.002, 1e-9);
  EXPECT_NEAR(f0.dt, 0.002, 1e-9);
  p.end_frame(t0 + milliseconds(10));
  EXPECT_EQ(p.next_due(), t0 + milliseconds(50));

  auto f1 = p.begin_frame(t0 + milliseconds(51));
  EXPECT_NEAR(f1.t, 0.051, 1e-9);
  EXPECT_NEAR(f1.dt, 0.049, 1e-9) << "dt: since the previous frame began";
  p.end_frame(t0 + milliseconds(60));
  EXPECT_EQ(p.next_due(), t0 + milliseconds(100)) << "due times stay on the grid, not drift with the start";
  EXPECT_NEAR(p.seconds_at(t0 + milliseconds(1500)), 1.5, 1e-9);
}

TEST(FramePacer, ALateFrameDoesNotBurstToCatchUp) {
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  FramePacer p(10.0, t0);
  p.begin_frame(t0);
  p.end_frame(t0 + milliseconds(350));  // 3.5 periods late
  EXPECT_EQ(p.next_due(), t0 + milliseconds(350)) << "the next frame is due now, then one period on";
  p.begin_frame(t0 + milliseconds(350));
  p.end_frame(t0 + milliseconds(360));
  EXPECT_EQ(p.next_due(), t0 + milliseconds(450));
}

TEST(WaitForFrame, PollsWithTheTimeLeftUntilTheFrameIsDue) {
  FramePacer p(5.0, Clock::now());  // due at once
  p.begin_frame(Clock::now());
  p.end_frame(Clock::now());  // next due in 200 ms
  std::vector<milliseconds> timeouts;
  wait_for_frame(p, [] { return false; }, [&](milliseconds timeout) {
    timeouts.push_back(timeout);
    std::this_thread::sleep_for(std::min(timeout, milliseconds(5)));  // a poll that returns early
  });
  EXPECT_GE(Clock::now(), p.next_due());
  ASSERT_GE(timeouts.size(), 2u) << "an early return polls again";
  EXPECT_LE(timeouts.front(), milliseconds(200));
  for (std::size_t i = 1; i < timeouts.size(); ++i) EXPECT_LE(timeouts[i], timeouts[i - 1]);
}

TEST(WaitForFrame, ReturnsAtOnceWhenDueOrStopped) {
  FramePacer due(1.0, Clock::now());
  int polls = 0;
  wait_for_frame(due, [] { return false; }, [&](milliseconds) { ++polls; });
  EXPECT_EQ(polls, 0) << "a due frame is not delayed";

  FramePacer later(1.0, Clock::now());
  later.begin_frame(Clock::now());
  later.end_frame(Clock::now());  // next due in 1 s
  bool stop = false;
  const auto before = Clock::now();
  wait_for_frame(later, [&] { return stop; }, [&](milliseconds) { stop = true; });
  EXPECT_LT(Clock::now() - before, milliseconds(500)) << "a stop ends the wait";
}

}  // namespace
}  // namespace meter::view
