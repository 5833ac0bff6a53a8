#include "meter/controller/mapping/signal_period.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <vector>

namespace meter::controller {

namespace {

// Distinct switch values covered by the ranges, saturating at UINT64_MAX.
std::uint64_t count_values(std::vector<MuxRange> ranges) {
  std::sort(ranges.begin(), ranges.end(), [](const MuxRange& a, const MuxRange& b) { return a.lo < b.lo; });
  std::uint64_t total = 0;
  bool open = false;
  MuxRange cur{0, 0};
  auto flush = [&] {
    if (!open) return;
    const std::uint64_t n = cur.hi - cur.lo;  // + 1 below, saturating
    total = (n >= UINT64_MAX - total) ? UINT64_MAX : total + n + 1;
  };
  for (const MuxRange& r : ranges) {
    if (r.hi < r.lo) continue;
    if (open && r.lo <= cur.hi + (cur.hi < UINT64_MAX ? 1 : 0)) {
      cur.hi = std::max(cur.hi, r.hi);
      continue;
    }
    flush();
    cur = r;
    open = true;
  }
  flush();
  return total;
}

std::optional<int> period(const DbcMessage& m, int signal, int depth) {
  if (!m.cycle_time_ms) return std::nullopt;
  if (signal < 0 || static_cast<std::size_t>(signal) >= m.signals.size() || depth > 8) return m.cycle_time_ms;
  const DbcSignal& s = m.signals[static_cast<std::size_t>(signal)];
  if (s.mux_switch < 0 || s.mux_ranges.empty()) return m.cycle_time_ms;
  const std::optional<int> switch_period = period(m, s.mux_switch, depth + 1);
  if (!switch_period) return std::nullopt;
  std::vector<MuxRange> pages;
  for (const DbcSignal& other : m.signals)
    if (other.mux_switch == s.mux_switch) pages.insert(pages.end(), other.mux_ranges.begin(), other.mux_ranges.end());
  const std::uint64_t n = count_values(pages), k = std::min(count_values(s.mux_ranges), n);
  const std::uint64_t frames = n - k + 1;
  const auto ms = static_cast<long double>(*switch_period) * static_cast<long double>(frames);
  return ms >= INT_MAX ? INT_MAX : static_cast<int>(ms);
}

}  // namespace

std::optional<int> signal_period_ms(const DbcMessage& m, int signal) { return period(m, signal, 0); }

}  // namespace meter::controller
