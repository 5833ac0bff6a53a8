// Per-stage time accounting for the view's pipeline (as CUBE measured its stages): how long each
// stage was busy, waited for input (an empty buffer, the frame clock, the GPU) and waited for space
// in its output buffer. Counters are atomics: the stage's thread adds, the --stats printer reads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

namespace meter::runner {

// A stage's totals since it started (or over a window: the difference of two readings).
struct StageTimes {
  std::string name;
  int lane = 0;  // the thread it runs on: stages of one lane share that thread's time
  std::int64_t busy_ns = 0, wait_in_ns = 0, wait_out_ns = 0;
  std::uint64_t items = 0;  // frames (or polls) it handled
};

// `now` minus `before` of the same stage (counters only grow).
StageTimes since(const StageTimes& now, const StageTimes& before);

class StageMeter {
 public:
  StageMeter(std::string name, int lane) : name_(std::move(name)), lane_(lane) {}
  StageMeter(const StageMeter&) = delete;
  StageMeter& operator=(const StageMeter&) = delete;

  void busy(std::int64_t ns) { busy_.fetch_add(ns, std::memory_order_relaxed); }
  void waited_input(std::int64_t ns) { wait_in_.fetch_add(ns, std::memory_order_relaxed); }
  void waited_output(std::int64_t ns) { wait_out_.fetch_add(ns, std::memory_order_relaxed); }
  void item() { items_.fetch_add(1, std::memory_order_relaxed); }
  // Time already counted busy (inside a BusyScope) that was a wait for output space after all.
  void busy_was_output_wait(std::int64_t ns) {
    busy_.fetch_sub(ns, std::memory_order_relaxed);
    wait_out_.fetch_add(ns, std::memory_order_relaxed);
  }
  StageTimes read() const;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  int lane_;
  std::atomic<std::int64_t> busy_{0}, wait_in_{0}, wait_out_{0};
  std::atomic<std::uint64_t> items_{0};
};

// Steady-clock nanoseconds since `began`.
std::int64_t ns_since(std::chrono::steady_clock::time_point began);

// Times the enclosing scope as busy time of `meter` (and counts an item unless told not to).
class BusyScope {
 public:
  explicit BusyScope(StageMeter& meter, bool counts_item = true)
      : meter_(meter), counts_(counts_item), began_(std::chrono::steady_clock::now()) {}
  ~BusyScope() {
    meter_.busy(ns_since(began_));
    if (counts_) meter_.item();
  }
  BusyScope(const BusyScope&) = delete;
  BusyScope& operator=(const BusyScope&) = delete;

 private:
  StageMeter& meter_;
  bool counts_;
  std::chrono::steady_clock::time_point began_;
};

}  // namespace meter::runner
