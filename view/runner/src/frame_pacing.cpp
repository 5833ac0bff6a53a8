#include "meter/runner/frame_pacing.hpp"

#include <algorithm>
#include <thread>

namespace meter::runner {

FramePacer::FramePacer(double fps, Clock::time_point start)
    : period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps))),
      start_(start),
      next_(start),
      last_(start),
      last_change_(start - period_) {}

double FramePacer::seconds_at(Clock::time_point now) const {
  return std::chrono::duration<double>(now - start_).count();
}

FramePacer::Clock::time_point FramePacer::due_with_change(Clock::time_point arrived) const {
  return std::min(next_, std::max(arrived, last_change_ + period_));
}

FramePacer::FrameTime FramePacer::begin_frame(Clock::time_point now, bool draws_change) {
  FrameTime ft;
  if (draws_change) last_change_ = now;
  if (now < next_) next_ = now;  // early, for a change: the grid restarts at this frame
  ft.dt = std::chrono::duration<double>(now - last_).count();
  ft.t = seconds_at(now);
  last_ = now;
  return ft;
}

bool FramePacer::end_frame(Clock::time_point now) {
  next_ += period_;
  if (next_ >= now) return false;
  next_ = now;  // late: do not burst to catch up
  return true;
}

void wait_for_frame(const FramePacer& pacer, const std::function<bool()>& stop,
                    const std::function<void(std::chrono::milliseconds)>& poll) {
  using Clock = FramePacer::Clock;
  const auto next = pacer.next_due();
  while (!stop()) {
    const auto now = Clock::now();
    if (now >= next) break;
    poll(std::chrono::duration_cast<std::chrono::milliseconds>(next - now));
    if (Clock::now() < next && next - Clock::now() < std::chrono::milliseconds(1)) std::this_thread::sleep_until(next);
  }
}

void wait_for_change_or_frame(const FramePacer& pacer, std::optional<FramePacer::Clock::time_point>& changed_since,
                              const std::function<bool()>& stop,
                              const std::function<bool(std::chrono::milliseconds)>& poll) {
  using Clock = FramePacer::Clock;
  while (!stop()) {
    const auto due = changed_since ? pacer.due_with_change(*changed_since) : pacer.next_due();
    const auto now = Clock::now();
    if (now >= due) break;
    if (due - now < std::chrono::milliseconds(1)) {
      std::this_thread::sleep_until(due);
      continue;
    }
    if (poll(std::chrono::duration_cast<std::chrono::milliseconds>(due - now)) && !changed_since)
      changed_since = Clock::now();
  }
}

}  // namespace meter::runner
