// What --stats prints: each stage's share of the wall time busy, waiting for input and waiting for
// output space over a window, and the bottleneck named in words by CUBE's rule (the stage whose
// producer waits on its full input buffer, or that drops frames there). Pure.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/runner/stage_meter.hpp"

namespace meter::runner {

struct PipelineWindow {
  std::vector<StageTimes> stages;  // in pipeline order, each over the window
  std::int64_t wall_ns = 0;        // the window's length (> 0)
  std::uint64_t dropped = 0;       // frames the output buffer refused in the window (--dump-policy drop)
};

// "intake busy 1 % in 92 % out 0 % (600) | evaluate busy 3 % ..." (items in parentheses), whole
// percents of the window (at most 100: a slice counts in the window where it ends).
std::string format_stage_shares(const PipelineWindow& window);

struct Bottleneck {
  std::string stage;  // empty: no stage is saturated
  std::string text;   // e.g. "encode busy 62 %, readback waited 41 % on it: encode is the bottleneck"
};

// CUBE's rule: a stage that waited at least kBlocked of the window for space in its output buffer
// is held back by the thread after it (the first stage after it on another thread, and the stages
// of that thread), and the busiest stage there is the bottleneck. Otherwise
// the busiest stage is, when its thread was busy at least kSaturated of the window or frames were
// dropped at a buffer; else none is ("no bottleneck: intake waited 88 % for input (the frame
// clock, the link), busiest render 9 %"). The wait quoted is the nearest upstream stage on another
// thread waiting for output space (it waited on the bottleneck; quoted when it waited at all or
// frames were dropped), or else the next downstream stage on another thread that waited for input
// (a GPU lane, which never waits for the loop, is not quoted).
Bottleneck find_bottleneck(const PipelineWindow& window);
inline constexpr double kSaturated = 0.75;
inline constexpr double kBlocked = 0.10;

}  // namespace meter::runner
