#include "meter/view/dump_policy.hpp"

#include <algorithm>

namespace meter::view {

DumpPolicy::DumpPolicy(int every, std::vector<double> at_times, bool dump_last)
    : every_(every), at_(std::move(at_times)), dump_last_(dump_last) {
  std::sort(at_.begin(), at_.end());
}

DumpChoice DumpPolicy::decide(std::uint64_t frame, double t, bool requested) {
  DumpChoice c;
  c.asked = requested;
  for (; next_at_ < at_.size() && at_[next_at_] <= t; ++next_at_) c.asked = true;
  c.write = c.asked || (every_ > 0 && frame % static_cast<std::uint64_t>(every_) == 0);
  return c;
}

}  // namespace meter::view
