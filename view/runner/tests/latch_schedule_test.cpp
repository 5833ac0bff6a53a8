// Late latching on plain times: a simulated compositor latches every period at its own phase,
// sends the frame callback `callback_after` later and presents `present_after` after the latch;
// the client draws when LatchSchedule says and takes `render(frame)` to commit.
#include "meter/runner/latch_schedule.hpp"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kPeriod = 16'666'667;

struct Compositor {
  std::int64_t phase = 3 * kMs;           // latches at phase + k * period
  std::int64_t callback_after = 1 * kMs;  // the frame callback arrives this long after the latch
  std::int64_t present_after = 16 * kMs;  // "presented" is stamped this long after the latch (Weston headless)
  bool feedback = true;

  std::int64_t latch_at_or_after(std::int64_t t) const {
    const std::int64_t k = (t - phase + kPeriod - 1) / kPeriod;
    return phase + std::max<std::int64_t>(0, k) * kPeriod;
  }
};

struct Shown {
  std::uint64_t frame;
  std::int64_t start, target, latch;
  LatchReason reason;
};

// The client's loop against the compositor: each frame drawn as soon as the schedule allows after
// the previous one's frame callback, feedback arriving at its presentation time; time goes on
// from one run() to the next.
class Sim {
 public:
  explicit Sim(LatchSchedule& s) : s_(s) {}
  Compositor c;
  std::int64_t read_after = 100'000;  // the loop reads the callback this much after it came

  std::vector<Shown> run(int frames, const std::function<std::int64_t(int)>& render) {
    std::vector<Shown> shown;
    for (int f = 0; f < frames; ++f, ++frame_) {
      while (!feedback_.empty() && feedback_.front().second <= now_) {  // in order, as stamped by now
        s_.presented(feedback_.front().first, false, feedback_.front().second, kPeriod);
        feedback_.erase(feedback_.begin());
      }
      const LatchDecision d = s_.decide(now_);
      const std::int64_t start = std::max(now_, d.start_ns);
      const std::int64_t committed = start + render(f);
      s_.committed(frame_, d, start, committed);
      const std::int64_t latch = c.latch_at_or_after(committed);
      shown.push_back({frame_, start, d.target_ns, latch, d.reason});
      if (c.feedback) feedback_.emplace_back(frame_, latch + c.present_after);
      s_.latched(latch + c.callback_after);
      now_ = latch + c.callback_after + read_after;
    }
    return shown;
  }

 private:
  LatchSchedule& s_;
  std::int64_t now_ = 100 * kMs;
  std::uint64_t frame_ = 0;
  std::vector<std::pair<std::uint64_t, std::int64_t>> feedback_;
};

int missed_after(const std::vector<Shown>& shown, std::size_t from) {
  int n = 0;
  for (std::size_t i = from; i < shown.size(); ++i) n += shown[i].target != 0 && shown[i].latch > shown[i].target;
  return n;
}

TEST(LatchSchedule, FramesThatFitStartLateAndMakeTheirLatch) {
  LatchSchedule s;
  Sim sim(s);
  const Compositor& c = sim.c;
  const auto shown = sim.run(600, [](int) { return 4 * kMs; });
  EXPECT_EQ(shown.front().reason, LatchReason::NoPeriod) << "the first frame is drawn at the callback";
  // Settled: each frame starts within render + margin before its latch, the margin at most 2 ms
  // over the compositor's callback delay (the latch is that much before the callback predicts).
  for (std::size_t i = 300; i < shown.size(); ++i) {
    ASSERT_EQ(shown[i].reason, LatchReason::Late) << i;
    const std::int64_t lead = shown[i].latch - shown[i].start;
    EXPECT_GE(lead, 4 * kMs) << i;
    EXPECT_LE(lead, 4 * kMs + c.callback_after + 2 * kMs) << i;
  }
  EXPECT_EQ(missed_after(shown, 300), 0);
  EXPECT_LE(s.missed(), 2u) << "settling from the safe start costs a miss or two at most";
  EXPECT_EQ(s.render_estimate_ns(), 4 * kMs);
  // Against drawing at the callback: the state is drawn ~9 ms nearer to the latch.
  EXPECT_GE(shown.back().start - (shown.back().latch - kPeriod + c.callback_after), 8 * kMs);
}

TEST(LatchSchedule, ARenderThatSpikesMissesOnceAndMovesTheStartEarlier) {
  LatchSchedule s;
  Sim sim(s);
  sim.run(400, [](int) { return 4 * kMs; });
  const std::int64_t margin = s.margin_ns();
  const std::uint64_t missed = s.missed();
  // One frame takes 5 ms longer than any before: it misses its latch.
  const auto shown = sim.run(3, [](int f) { return f == 0 ? 9 * kMs : 4 * kMs; });
  EXPECT_GT(shown[0].latch, shown[0].target);
  EXPECT_EQ(missed_after(shown, 1), 0) << "the frames after it make theirs";
  EXPECT_EQ(s.missed(), missed + 1);
  EXPECT_GE(s.margin_ns(), margin + 750'000) << "the start moved earlier";
  EXPECT_LE(s.margin_ns(), margin + kMs);
  EXPECT_EQ(s.render_estimate_ns(), 4 * kMs) << "one spike in 64 renders is above the 95th percentile";
}

TEST(LatchSchedule, AFrameFasterThanItsEstimateMakesAnEarlierLatchAndCountsAsOnTime) {
  LatchSettings unsettled;
  unsettled.settle_run = 1'000'000;  // the margin stays at its safe 8 ms
  LatchSchedule s(unsettled);
  Sim sim(s);
  // Renders of 15.9 ms, the callback read 1 ms late: with the least margin they cannot make the
  // next latch, frames are started for the one after it (8 ms + 15.9 ms before it).
  sim.read_after = kMs;
  sim.run(100, [](int) { return 15'900'000; });
  const std::uint64_t missed = s.missed();
  // Then 3 ms: until the estimate learns it, frames make the latch before their target.
  const auto shown = sim.run(300, [](int) { return 3 * kMs; });
  int early = 0;
  for (const auto& f : shown) early += f.target != 0 && f.latch < f.target - kPeriod / 2;
  EXPECT_GT(early, 30);
  EXPECT_EQ(s.missed(), missed) << "early frames do not make the frames on time after them look late";
  EXPECT_EQ(missed_after(shown, 0), 0);
  EXPECT_LE(shown.back().latch - shown.back().start, 3 * kMs + 8 * kMs) << "the estimate learnt the 3 ms";
}

TEST(LatchSchedule, FollowsACompositorThatLatchesAtAnotherPhase) {
  for (const std::int64_t phase : {0 * kMs, 7 * kMs, 13 * kMs}) {
    LatchSchedule s;
    Sim sim(s);
    sim.c.phase = phase;
    sim.c.callback_after = 3 * kMs;  // a compositor whose callbacks come 3 ms after its latch
    const auto shown = sim.run(600, [](int) { return 2 * kMs; });
    EXPECT_EQ(missed_after(shown, 300), 0) << phase;
    EXPECT_LE(s.missed(), 2u) << phase;
    // Settled at no more than 2 ms over what the phase error needs (3 ms): the frame starts at
    // most 2 ms earlier than its 2 ms render needs.
    EXPECT_GE(s.margin_ns(), 3 * kMs) << phase;
    EXPECT_LE(s.margin_ns(), 5 * kMs) << phase;
    for (std::size_t i = 300; i < shown.size(); ++i) {
      ASSERT_EQ(shown[i].reason, LatchReason::Late) << phase;
      EXPECT_GE(shown[i].latch - shown[i].start, 2 * kMs) << phase << " " << i;
      EXPECT_LE(shown[i].latch - shown[i].start, 4 * kMs) << phase << " " << i;
    }
  }
}

TEST(LatchSchedule, WithoutFeedbackItDrawsAtTheCallback) {
  LatchSchedule s;
  Sim sim(s);
  sim.c.feedback = false;
  const auto shown = sim.run(50, [](int) { return 4 * kMs; });
  for (const auto& f : shown) {
    EXPECT_EQ(f.reason, LatchReason::NoPeriod);
    EXPECT_EQ(f.target, 0);
  }
  // Feedback that stops: once the oldest frame drawn for a latch has waited 250 ms for it, back to the callback.
  LatchSchedule t;
  Sim stops(t);
  stops.run(100, [](int) { return 4 * kMs; });
  stops.c.feedback = false;
  const auto without = stops.run(40, [](int) { return 4 * kMs; });
  EXPECT_EQ(without.front().reason, LatchReason::Late);
  EXPECT_EQ(without.back().reason, LatchReason::NoFeedback);
  EXPECT_EQ(without.back().target, 0);
}

TEST(LatchSchedule, ALongRenderSqueezesTheMarginAndOneLongerThanThePeriodDrawsAtOnce) {
  LatchSchedule s;
  Sim sim(s);
  // A render of 15 ms leaves 1.7 ms of the period: the frame starts at once, for the next latch.
  const auto squeezed = sim.run(100, [](int) { return 15 * kMs; });
  EXPECT_EQ(squeezed.back().reason, LatchReason::Late);
  EXPECT_EQ(squeezed.back().start, squeezed.back().target - kPeriod + 100'000) << "read 0.1 ms after the callback";
  const LatchDecision d = s.decide(10'000 * kMs);
  EXPECT_EQ(d.reason, LatchReason::Idle) << "the last latch is seconds old";
  EXPECT_EQ(d.start_ns, 10'000 * kMs);
  const auto shown = sim.run(5, [](int) { return 17 * kMs; });
  EXPECT_EQ(shown.back().reason, LatchReason::RenderTooLong);
  EXPECT_EQ(shown.back().target, 0);
}

TEST(LatchSchedule, DiscardedFramesCountAsMissedAndTheOptionIsChecked) {
  LatchSchedule s;
  s.presented(0, false, 10 * kMs, kPeriod);
  s.latched(10 * kMs);
  const LatchDecision d = s.decide(11 * kMs);
  ASSERT_EQ(d.reason, LatchReason::Late);
  EXPECT_EQ(d.target_ns, 10 * kMs + kPeriod);
  EXPECT_EQ(d.start_ns, d.target_ns - 8 * kMs) << "no render yet: the safe margin (8 ms, under half a period)";
  s.committed(1, d, d.start_ns, d.start_ns + kMs);
  s.presented(1, true, 0, 0);
  EXPECT_EQ(s.missed(), 1u);
  EXPECT_EQ(parse_latch_pacing("late"), LatchPacing::Late);
  EXPECT_EQ(parse_latch_pacing("callback"), LatchPacing::Callback);
  EXPECT_THROW(parse_latch_pacing("vblank"), ViewError);
}

}  // namespace
}  // namespace meter::runner
