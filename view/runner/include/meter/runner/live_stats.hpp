// --stats: the live pipeline's stage meters read every interval (and at exit) and printed as each
// stage's busy / waiting-for-input / waiting-for-output shares with the bottleneck named
// (pipeline_report.hpp). The render loop's stages (lane 1) are metered here; the writer thread's
// check and encode stages by the PngWriter.
#pragma once

#include <chrono>
#include <ostream>

#include "meter/runner/pipeline_report.hpp"
#include "meter/runner/png_writer.hpp"
#include "meter/runner/stage_meter.hpp"

namespace meter::runner {

class LiveStats {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kLane = 1;  // the render loop (GL thread)

  // interval_s <= 0: never printed while running (totals() still works).
  LiveStats(const PngWriter& writer, double interval_s, Clock::time_point start);

  StageMeter intake{"intake", kLane}, evaluate{"evaluate", kLane}, plan{"plan", kLane}, render{"render", kLane},
      readback{"readback", kLane};

  // The window since the previous print (or since start).
  PipelineWindow window(Clock::time_point now) const;
  // Everything since start.
  PipelineWindow totals(Clock::time_point now) const;
  // Prints "meter-view: stats <t> s: <shares>; <bottleneck>" when an interval has passed.
  void print_if_due(Clock::time_point now, std::ostream& log);
  static void print(const PipelineWindow& w, double t, std::ostream& log);

 private:
  std::vector<StageTimes> read() const;

  const PngWriter& writer_;
  Clock::duration interval_;
  Clock::time_point start_, last_;
  std::vector<StageTimes> last_times_;
  std::uint64_t last_dropped_ = 0;
};

}  // namespace meter::runner
