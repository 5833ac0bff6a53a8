// The live view's frame clock: frames at a fixed rate on the view's own clock, decoupled from
// message arrival. A late frame moves the schedule on instead of bursting frames to catch up.
#pragma once

#include <chrono>
#include <functional>
#include <optional>

namespace meter::runner {

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
  // Latency-aware frames (--pipeline concurrent): changed values waiting since `arrived` may be
  // drawn by a frame starting at `arrived`, but not before one period after the previous frame
  // that drew a change (the frame rate stays at most --fps) and never later than the next tick.
  // A change is then drawn within one period plus the render time of its arrival.
  Clock::time_point due_with_change(Clock::time_point arrived) const;

  // A frame begins at `now`; `draws_change`: it draws changed values (due_with_change applies to
  // the next one). A frame that begins before its tick (for a change) moves the tick grid: the
  // next tick is a period after it.
  FrameTime begin_frame(Clock::time_point now, bool draws_change = false);
  // The frame is done at `now`: the next one is due a period after the last due time, or at
  // `now` when that has passed already. Returns true when it had passed: this frame missed its
  // deadline (it ended after the next frame was due).
  bool end_frame(Clock::time_point now);

 private:
  Clock::duration period_;
  Clock::time_point start_, next_, last_, last_change_;
};

// Waits until the next frame is due, servicing the link meanwhile: `poll(timeout)` is called with
// at most the time left (it may return earlier); the last sub-millisecond is slept. Returns early
// once `stop()` is true.
void wait_for_frame(const FramePacer& pacer, const std::function<bool()>& stop,
                    const std::function<void(std::chrono::milliseconds)>& poll);

// The latency-aware wait: as wait_for_frame, but returns as soon as changed values may be drawn
// (FramePacer::due_with_change). `changed_since`: when the first change not yet drawn arrived (set
// here when a `poll(timeout)` returns true, i.e. applied changes; the caller clears it when a frame
// begins).
void wait_for_change_or_frame(const FramePacer& pacer, std::optional<FramePacer::Clock::time_point>& changed_since,
                              const std::function<bool()>& stop,
                              const std::function<bool(std::chrono::milliseconds)>& poll);

}  // namespace meter::runner
