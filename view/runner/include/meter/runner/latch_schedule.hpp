// Late latching: when to start drawing a frame so that it shows the newest state at the
// compositor's (or the CRTC's) next latch. A compositor takes the surface's last commit at its
// repaint (the frame callbacks are sent right then) and a CRTC the last queued flip at its vblank;
// a frame drawn as soon as the previous one was taken waits a period for that latch with the state
// it drew. LatchSchedule predicts the next latch from the times the screen took frames (frame
// callbacks, flip events) and the refresh period of the presentation feedback, and starts the draw
// at (latch - render estimate - margin): the render estimate is a high percentile of the recent
// renders (draw start -> commit), the margin adapts: a frame whose feedback says it came a refresh
// later after its target latch than most recent frames (it missed its latch) moves the start
// earlier, a run of frames on time moves it later, within bounds; a render that leaves less than the
// margin squeezes it (the frame starts at once, still for the next latch). Without a period, a
// latch or feedback, with an idle compositor, or with a render that leaves no room in the period,
// it says: draw now (at the callback). Plain data: times in (CLOCK_MONOTONIC nanoseconds), a
// decision out; no clock, socket or GL.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>

namespace meter::runner {

// --latch: callback (draw as soon as the display took the frame before) or late (LatchSchedule).
enum class LatchPacing { Callback, Late };
// "callback" or "late"; anything else throws ViewError naming the option and the choices.
LatchPacing parse_latch_pacing(const std::string& text);
const char* latch_pacing_name(LatchPacing pacing);

struct LatchSettings {
  // The margin before the predicted latch starts at its most (a safe start: the first frames make
  // their latch, so their feedback tells what "on time" looks like) and settles from there.
  std::int64_t max_margin_ns = 8'000'000;  // also at most half a period
  std::int64_t min_margin_ns = 500'000;
  std::int64_t settle_step_ns = 500'000;   // before the first miss: this much later ...
  int settle_run = 10;                     // ... every this many frames on time in a row
  std::int64_t on_time_step_ns = 250'000;  // after it: this much later ...
  int on_time_run = 60;                    // ... every this many frames on time in a row
  std::int64_t miss_step_ns = 1'000'000;   // a missed latch: the start this much earlier
  std::size_t render_window = 64;          // the recent renders the estimate is taken from
  double render_percentile = 95.0;         // the estimate: this percentile of them
  std::size_t offset_window = 256;         // the recent (presented - target) offsets, whose median is "on time"
  // A frame drawn for a latch with no feedback this long after that latch: feedback is missing,
  // the schedule falls back to drawing at the callback.
  std::int64_t feedback_timeout_ns = 250'000'000;
};

// Why a frame starts when it does (the summary counts each).
enum class LatchReason {
  Late,           // at the predicted latch less the render estimate and the margin
  NoPeriod,       // no refresh period known yet (no presentation feedback with one)
  NoLatch,        // the screen has not taken a frame yet
  Idle,           // the last latch is more than 1.5 periods old: the compositor idles, a commit restarts it
  NoFeedback,     // feedback stopped coming for frames drawn for a latch
  RenderTooLong,  // the render estimate and the least margin do not fit in a period
};
const char* latch_reason_name(LatchReason reason);

struct LatchDecision {
  std::int64_t start_ns = 0;   // draw at this time; at or before now: draw now
  std::int64_t target_ns = 0;  // the latch the frame is drawn for; 0: none (drawn at the callback)
  std::int64_t margin_ns = 0;  // the margin it was started with
  LatchReason reason = LatchReason::NoLatch;
};

class LatchSchedule {
 public:
  explicit LatchSchedule(LatchSettings settings = {});

  // The screen took a frame at `t_ns` (a frame callback arrived; a page flip's vblank). Older or
  // repeated times are ignored.
  void latched(std::int64_t t_ns);
  // Frame `frame`, started by `decision`, was drawn from `start_ns` and handed to the display at
  // `committed_ns` (a decision without a target latch is not judged).
  void committed(std::uint64_t frame, const LatchDecision& decision, std::int64_t start_ns, std::int64_t committed_ns);
  // Presentation feedback of frame `frame` (feedback comes in presentation order): presented at
  // `presented_ns` on an output refreshing every `refresh_ns` (0: unknown), or discarded.
  void presented(std::uint64_t frame, bool discarded, std::int64_t presented_ns, std::int64_t refresh_ns);

  LatchDecision decide(std::int64_t now_ns) const;

  std::int64_t period_ns() const { return period_ns_; }
  std::int64_t margin_ns() const { return margin_ns_; }
  std::int64_t render_estimate_ns() const;  // 0 before the first render
  std::uint64_t on_time() const { return on_time_; }
  std::uint64_t missed() const { return missed_; }

 private:
  struct Awaiting {
    std::int64_t target_ns, margin_ns, committed_ns;
  };
  void judge(const Awaiting& frame, bool missed);
  std::int64_t margin_limit() const;

  LatchSettings s_;
  std::int64_t margin_ns_;
  std::int64_t period_ns_ = 0;
  std::int64_t last_latch_ns_ = 0;
  std::deque<std::int64_t> renders_;
  std::deque<std::int64_t> offsets_;
  std::map<std::uint64_t, Awaiting> awaiting_;  // frames drawn for a latch, their feedback not in
  // Never settle below a margin that missed although its frame was committed before the latch
  // predicted for it (the prediction, not the render, was off).
  std::int64_t floor_ns_ = 0;
  bool settled_ = false;  // a miss was seen: settle slowly from now on
  int run_ = 0;
  std::uint64_t on_time_ = 0, missed_ = 0;
};

}  // namespace meter::runner
