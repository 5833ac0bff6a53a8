// The frame clock: period, the view's clock, no burst after a late frame, and the wait that
// services the link until the next frame is due.
#include "meter/runner/frame_pacing.hpp"

#include <algorithm>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace meter::runner {
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

// Latency-aware frames: a change is drawn as soon as the frame rate allows, not at the next tick.
TEST(FramePacer, AChangeAfterAnIdleSpellIsDueWhenItArrives) {
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  FramePacer p(10.0, t0);
  p.begin_frame(t0, true);
  p.end_frame(t0 + milliseconds(5));
  p.begin_frame(t0 + milliseconds(100));  // idle ticks draw no change
  p.end_frame(t0 + milliseconds(105));
  EXPECT_EQ(p.next_due(), t0 + milliseconds(200));
  EXPECT_EQ(p.due_with_change(t0 + milliseconds(130)), t0 + milliseconds(130))
      << "the last change was drawn 130 ms ago, more than a period: at once, not at the 200 ms tick";
}

TEST(FramePacer, ChangesComeAtMostOncePerPeriod) {
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  FramePacer p(10.0, t0);
  p.begin_frame(t0);
  p.end_frame(t0 + milliseconds(5));                                  // next tick at 100 ms
  p.begin_frame(t0 + milliseconds(60), true);  // early, for a change: the grid restarts here
  p.end_frame(t0 + milliseconds(70));
  EXPECT_EQ(p.next_due(), t0 + milliseconds(160)) << "the next tick a period after the early frame";
  EXPECT_EQ(p.due_with_change(t0 + milliseconds(80)), t0 + milliseconds(160))
      << "a change 20 ms after the last one waits for the period";
  p.begin_frame(t0 + milliseconds(160));  // an idle tick
  p.end_frame(t0 + milliseconds(165));
  EXPECT_EQ(p.due_with_change(t0 + milliseconds(300)), t0 + milliseconds(260))
      << "never later than the next tick";
}

TEST(WaitForChangeOrFrame, AChangeArrivingDuringTheWaitEndsItAtOnce) {
  const auto now = Clock::now();
  FramePacer p(1.0, now - milliseconds(1500));
  p.begin_frame(now - milliseconds(1500), true);  // the last change is older than a period
  p.end_frame(now - milliseconds(1490));
  p.begin_frame(now - milliseconds(500));  // an idle tick
  p.end_frame(now - milliseconds(490));    // next tick in ~500 ms
  std::optional<Clock::time_point> since;
  int polls = 0;
  const auto before = Clock::now();
  wait_for_change_or_frame(p, since, [] { return false; }, [&](milliseconds) {
    std::this_thread::sleep_for(milliseconds(2));
    return ++polls == 3;  // the third poll applies a change
  });
  EXPECT_EQ(polls, 3);
  ASSERT_TRUE(since.has_value()) << "the arrival is kept for the frame";
  EXPECT_LT(Clock::now() - before, milliseconds(300)) << "not held to the ~500 ms tick";
}

TEST(WaitForChangeOrFrame, WithoutChangesItWaitsForTheTick) {
  FramePacer p(20.0, Clock::now());
  p.begin_frame(Clock::now());
  p.end_frame(Clock::now());  // next due in 50 ms
  std::optional<Clock::time_point> since;
  wait_for_change_or_frame(p, since, [] { return false; }, [&](milliseconds t) {
    std::this_thread::sleep_for(std::min(t, milliseconds(5)));
    return false;
  });
  EXPECT_GE(Clock::now(), p.next_due());
  EXPECT_FALSE(since.has_value());
}

}  // namespace
}  // namespace meter::runner
