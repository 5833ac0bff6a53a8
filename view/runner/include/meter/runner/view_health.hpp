// The view's own faults as the STATUS back channel carries them (protocol kViewFault* bits):
// counted, and each held as a flag for kViewFaultHoldMs after it last happened, so the controller
// sees every fault even when STATUS frames coalesce. Pure: the caller passes the time.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>

namespace meter::runner {

class ViewHealth {
 public:
  using Clock = std::chrono::steady_clock;
  // fault: one kViewFault* bit.
  void report(std::uint32_t fault, Clock::time_point now);
  // The bits of every fault reported within the hold time before `now`.
  std::uint32_t flags(Clock::time_point now) const;
  // How often that fault was reported in total.
  std::uint64_t count(std::uint32_t fault) const;

 private:
  std::array<std::optional<Clock::time_point>, 32> last_{};
  std::array<std::uint64_t, 32> counts_{};
};

}  // namespace meter::runner
