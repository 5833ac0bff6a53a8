#include "meter/runner/view_health.hpp"

#include <bit>

#include "meter/protocol/wire.hpp"

namespace meter::runner {

namespace {
int bit_of(std::uint32_t fault) { return fault == 0 ? -1 : std::countr_zero(fault); }
}  // namespace

void ViewHealth::report(std::uint32_t fault, Clock::time_point now) {
  const int b = bit_of(fault);
  if (b < 0) return;
  last_[static_cast<std::size_t>(b)] = now;
  ++counts_[static_cast<std::size_t>(b)];
}

std::uint32_t ViewHealth::flags(Clock::time_point now) const {
  const auto hold = std::chrono::milliseconds(protocol::kViewFaultHoldMs);
  std::uint32_t out = 0;
  for (std::size_t b = 0; b < last_.size(); ++b)
    if (last_[b] && now - *last_[b] < hold) out |= 1U << b;
  return out;
}

std::uint64_t ViewHealth::count(std::uint32_t fault) const {
  const int b = bit_of(fault);
  return b < 0 ? 0 : counts_[static_cast<std::size_t>(b)];
}

}  // namespace meter::runner
