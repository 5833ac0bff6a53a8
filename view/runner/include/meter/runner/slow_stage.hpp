// Test only (hidden --inject-slow-stage STAGE:MS): one stage of the live pipeline made slower by a
// sleep inside its busy span, so that a real run shows `--stats` naming that stage the bottleneck
// (docs/pipeline.md), as the integrity monitor's injected faults show it detecting them.
#pragma once

#include <array>
#include <chrono>
#include <string>
#include <string_view>

namespace meter::runner {

// The live pipeline's stages a delay can go into, in pipeline order (the GPU's execution cannot be
// slowed from the CPU: it shows as the render stage waiting for it).
inline constexpr std::array<std::string_view, 7> kSlowableStages = {"intake", "evaluate", "plan",    "render",
                                                                    "readback", "check", "encode"};

struct SlowStage {
  std::string stage;  // empty: none
  std::chrono::nanoseconds delay{0};

  // Sleeps for the delay when `name` is the slow stage.
  void in(std::string_view name) const;
  // The delay when `name` is the slow stage, else zero.
  std::chrono::nanoseconds of(std::string_view name) const { return name == stage ? delay : std::chrono::nanoseconds(0); }
};

// "STAGE:MS" (MS a positive number of milliseconds, at most 1000); empty text: none. Throws
// ViewError naming the option, the text and what was expected. plan and render are timed inside the
// engine's render call in the sequential and concurrent loops: refused there (`overlapped` false).
SlowStage parse_slow_stage(const std::string& text, bool overlapped);

}  // namespace meter::runner
