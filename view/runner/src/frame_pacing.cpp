#include "meter/view/frame_pacing.hpp"

#include <thread>

namespace meter::view {

FramePacer::FramePacer(double fps, Clock::time_point start)
    : period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps))),
      start_(start),
      next_(start),
      last_(start) {}

double FramePacer::seconds_at(Clock::time_point now) const {
  return std::chrono::duration<double>(now - start_).count();
}

FramePacer::FrameTime FramePacer::begin_frame(Clock::time_point now) {
  FrameTime ft;
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

}  // namespace meter::view
