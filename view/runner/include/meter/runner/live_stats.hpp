// --stats: the live pipeline's stage meters read every interval (and at exit) and printed as each
// stage's busy / waiting-for-input / waiting-for-output shares with the bottleneck named
// (pipeline_report.hpp). The render loop's stages (lane 1) and the GPU's (lane 3) are metered here;
// the writer thread's check and encode stages by the PngWriter.
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
  static constexpr int kLane = 1;     // the render loop (GL thread)
  static constexpr int kGpuLane = 3;  // the GPU executing a fenced frame (the overlapped pipeline)

  // interval_s <= 0: never printed while running (totals() still works).
  LiveStats(const PngWriter& writer, double interval_s, Clock::time_point start);

  // gpu: from a fenced frame's submission to when it was last seen executing (the overlapped
  // pipeline; a lower bound of its execution, exact when a stage waited for it); zero in the other
  // loops, whose render stage waits for the GPU itself (glFinish).
  StageMeter intake{"intake", kLane}, evaluate{"evaluate", kLane}, plan{"plan", kLane}, render{"render", kLane},
      gpu{"gpu", kGpuLane}, readback{"readback", kLane};

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
