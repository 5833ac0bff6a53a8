#include "meter/runner/dump_policy.hpp"

#include <algorithm>
#include <cstdio>

#include "meter/runner/option_units.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

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

DumpPolicy dump_policy(const ViewOptions& options) {
  std::vector<double> at;
  for (const auto& text : options.dump_at) at.push_back(parse_time(text, "--dump-at"));
  return DumpPolicy(options.dump_every, std::move(at), options.dump_last);
}

std::string png_name(std::uint64_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(frame));
  return name;
}

}  // namespace meter::runner
