// The live view's frame clock: frames at a fixed rate on the view's own clock, decoupled from
// message arrival. A late frame moves the schedule on instead of bursting frames to catch up.
#pragma once

#include <chrono>
#include <functional>

namespace meter::view {

class FramePacer {
 public:
  using Clock = std::chrono::steady_clock;

  // fps > 0; `start` is time 0 on the view's clock (frames.csv time_s).
  FramePacer(double fps, Clock::time_point start);

  Clock::duration period() const { return period_; }
  Clock::time_point next_due() const { return next_; }
  // Seconds on the view's clock at `now`.
  double seconds_at(Clock::time_point now) const;

  struct FrameTime {
    double t = 0.0;   // seconds since start
    double dt = 0.0;  // seconds since the previous frame began (since start for the first)
  };
  // A frame begins at `now`.
  FrameTime begin_frame(Clock::time_point now);
  // The frame is done at `now`: the next one is due a period after the last due time, or at
  // `now` when that has passed already. Returns true when it had passed: this frame missed its
  // deadline (it ended after the next frame was due).
  bool end_frame(Clock::time_point now);

 private:
  Clock::duration period_;
  Clock::time_point start_, next_, last_;
};

// Waits until the next frame is due, servicing the link meanwhile: `poll(timeout)` is called with
// at most the time left (it may return earlier); the last sub-millisecond is slept. Returns early
// once `stop()` is true.
void wait_for_frame(const FramePacer& pacer, const std::function<bool()>& stop,
                    const std::function<void(std::chrono::milliseconds)>& poll);

}  // namespace meter::view
