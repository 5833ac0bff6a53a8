// meter-view's frame-rate governor in its render loops (live and play; docs/uniform-frame-rate.md):
// the frame pipeline's quality input (engine::FrameGovernor): asked with each frame's planned load
// between planning and drawing, then handed the frame's measured time (Governor::observe); or a
// fixed quality (--quality full | cheapest) for side-by-side runs. Also what the run shows of it:
// the frames.csv / timing CSV cells, the --stats line, the summary.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "meter/engine/governor/governor.hpp"
#include "meter/engine/pipeline/frame_governor.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

// The cost file meter-view reads for a package when --costs is not given (meter-calibrate writes it).
std::string default_costs_path(const std::string& package);

// Test-only --inject-cost NS_PER_PIXEL@FIRST-LAST: frames FIRST..LAST (the loop's frame numbers)
// take NS_PER_PIXEL ns longer per pixel they draw (busy time after the draw, measured with it).
struct CostInjection {
  double ns_per_pixel = 0.0;
  std::uint64_t first = 0, last = 0;
};
// Throws ViewError naming the option, the text and what was expected.
CostInjection parse_cost_injection(const std::string& text);

class GovernedFrames : public engine::FrameGovernor {
 public:
  using Clock = std::chrono::steady_clock;

  // Reads and binds the cost file when the governor is on or the quality is "cheapest". Throws
  // ViewError for options that contradict each other, a missing cost file (naming it and how to
  // make one) and, with the file's own message, a bad or stale one.
  GovernedFrames(engine::Renderer& renderer, const ViewOptions& options, std::ostream& log);

  bool governing() const { return governor_.has_value(); }
  double target_ms() const { return target_ms_; }

  // The governor's choice for the planned frame; none for the start-up frame (the first drawn: it
  // makes the targets and the static layer once, which no level makes fit the target; drawn at the
  // quality the run starts with) and when the governor is off.
  std::optional<engine::governor::QualityChoice> choose(const engine::governor::FrameLoad& planned) override;
  // The frame's measured time (with --inject-cost's busy time) handed to the governor; after the
  // start-up frame, every level the governor may take is drawn once (warm-up).
  void rendered(const engine::FrameTiming& timing, std::int64_t began_ns) override;
  // The last frame's cells (the governor's prediction, the measured time, the choice); nullptr
  // when the governor is off.
  const GovernorCells* cells() const override { return governor_ ? &cells_ : nullptr; }
  // With --stats: "meter-view: governor <t> s: ..." every interval (frames over the target,
  // measured p50 / max, the last prediction, the online scales, the units below full).
  void print_if_due(Clock::time_point now, std::ostream& log);
  // At exit, when a target was given: frames drawn, frames over the target, changes, the choice.
  void summary(std::ostream& log) const;

 private:
  void warm_up(double start_up_ms);
  void observe(double ms);

  engine::Renderer& renderer_;
  std::ostream* log_;  // the constructor's log: the warm-up after the start-up frame reports there
  double target_ms_ = 0.0;
  std::optional<engine::governor::Governor> governor_;
  std::optional<CostInjection> inject_;
  std::uint64_t frame_ = 0;
  GovernorCells cells_;
  // The choice cells_.reduced / units_reduced describe: the summary is rebuilt only when it changes.
  std::optional<engine::governor::QualityChoice> described_;
  // Counters: whole run and the --stats interval.
  std::uint64_t drawn_ = 0, over_ = 0;
  std::vector<double> window_ms_;
  std::uint64_t window_over_ = 0;
  Clock::duration interval_{};
  Clock::time_point start_, last_print_;
};

}  // namespace meter::runner
