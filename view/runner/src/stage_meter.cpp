#include "meter/runner/stage_meter.hpp"

namespace meter::runner {

StageTimes since(const StageTimes& now, const StageTimes& before) {
  StageTimes d = now;
  d.busy_ns -= before.busy_ns;
  d.wait_in_ns -= before.wait_in_ns;
  d.wait_out_ns -= before.wait_out_ns;
  d.items -= before.items;
  return d;
}

StageTimes StageMeter::read() const {
  StageTimes t;
  t.name = name_;
  t.lane = lane_;
  t.busy_ns = busy_.load(std::memory_order_relaxed);
  t.wait_in_ns = wait_in_.load(std::memory_order_relaxed);
  t.wait_out_ns = wait_out_.load(std::memory_order_relaxed);
  t.items = items_.load(std::memory_order_relaxed);
  return t;
}

std::int64_t ns_since(std::chrono::steady_clock::time_point began) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - began).count();
}

}  // namespace meter::runner
