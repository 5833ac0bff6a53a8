#include "meter/runner/pipeline_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace meter::runner {
namespace {

// Whole percent of the window, at most 100: a slice is counted in the window where it ends, so a
// long encode crossing a window's start would otherwise show above 100 %.
int percent(std::int64_t ns, std::int64_t wall) {
  if (wall <= 0) return 0;
  const double share = std::min(1.0, static_cast<double>(ns) / static_cast<double>(wall));
  return static_cast<int>(std::lround(100.0 * share));
}

std::string pct(std::int64_t ns, std::int64_t wall) { return std::to_string(percent(ns, wall)) + " %"; }

}  // namespace

std::string format_stage_shares(const PipelineWindow& w) {
  std::string out;
  for (const auto& s : w.stages) {
    if (!out.empty()) out += " | ";
    out += s.name + " busy " + pct(s.busy_ns, w.wall_ns) + " in " + pct(s.wait_in_ns, w.wall_ns) + " out " +
           pct(s.wait_out_ns, w.wall_ns) + " (" + std::to_string(s.items) + ")";
  }
  return out;
}

Bottleneck find_bottleneck(const PipelineWindow& w) {
  Bottleneck b;
  if (w.stages.empty() || w.wall_ns <= 0) return b;
  const auto share = [&](std::int64_t ns) { return static_cast<double>(ns) / static_cast<double>(w.wall_ns); };
  std::map<int, std::int64_t> lane_busy;
  for (const auto& s : w.stages) lane_busy[s.lane] += s.busy_ns;
  auto busiest = [&](std::size_t from) {
    std::size_t top = from;
    for (std::size_t i = from; i < w.stages.size(); ++i)
      if (w.stages[i].busy_ns > w.stages[top].busy_ns) top = i;
    return top;
  };
  // A producer blocked on its full output buffer: the bottleneck is downstream of it, on the
  // busiest stage of the threads after it (CUBE's reading of its Table 1).
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < w.stages.size(); ++i)
    if (w.stages[i].wait_out_ns > w.stages[blocked].wait_out_ns) blocked = i;
  std::size_t top = busiest(0);
  if (share(w.stages[blocked].wait_out_ns) >= kBlocked && blocked + 1 < w.stages.size()) {
    std::size_t first_after = blocked + 1;
    while (first_after < w.stages.size() && w.stages[first_after].lane == w.stages[blocked].lane) ++first_after;
    // The thread it waits on is the first one after it: the busiest stage of that thread (not of
    // a thread further on: render waiting on the GPU is not held back by the PNG writer).
    if (first_after < w.stages.size()) {
      top = first_after;
      for (std::size_t i = first_after; i < w.stages.size(); ++i)
        if (w.stages[i].lane == w.stages[first_after].lane && w.stages[i].busy_ns > w.stages[top].busy_ns) top = i;
    }
  } else if (share(lane_busy[w.stages[top].lane]) < kSaturated && w.dropped == 0) {
    const StageTimes& first = w.stages.front();
    b.text = "no bottleneck: " + first.name + " waited " + pct(first.wait_in_ns, w.wall_ns) +
             " for input (the frame clock, the link), busiest " + w.stages[top].name + " " +
             pct(w.stages[top].busy_ns, w.wall_ns);
    return b;
  }
  const StageTimes& s = w.stages[top];
  b.stage = s.name;
  b.text = s.name + " busy " + pct(s.busy_ns, w.wall_ns);
  if (percent(lane_busy[s.lane], w.wall_ns) > percent(s.busy_ns, w.wall_ns))
    b.text += " (its thread " + pct(lane_busy[s.lane], w.wall_ns) + ")";
  // Upstream on another thread: it waited for space in the buffer the bottleneck empties.
  const StageTimes* waiter = nullptr;
  for (std::size_t i = top; i-- > 0;) {
    if (w.stages[i].lane != s.lane) {
      waiter = &w.stages[i];
      break;
    }
  }
  if (waiter && (waiter->wait_out_ns > 0 || w.dropped > 0)) {
    b.text += ", " + waiter->name + " waited " + pct(waiter->wait_out_ns, w.wall_ns) + " on it";
  } else {
    for (std::size_t i = top + 1; i < w.stages.size(); ++i) {
      if (w.stages[i].lane != s.lane && w.stages[i].wait_in_ns > 0) {
        b.text += ", " + w.stages[i].name + " waited " + pct(w.stages[i].wait_in_ns, w.wall_ns) + " for its output";
        break;
      }
    }
  }
  if (w.dropped > 0) b.text += ", " + std::to_string(w.dropped) + " frames dropped";
  b.text += ": " + s.name + " is the bottleneck";
  return b;
}

}  // namespace meter::runner
