#include "meter/runner/live_stats.hpp"

#include <cstdio>

namespace meter::runner {

LiveStats::LiveStats(const PngWriter& writer, double interval_s, Clock::time_point start)
    : writer_(writer),
      interval_(interval_s > 0 ? std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_s))
                               : Clock::duration::zero()),
      start_(start),
      last_(start),
      last_times_(read()) {}

std::vector<StageTimes> LiveStats::read() const {
  return {intake.read(), evaluate.read(), plan.read(), render.read(), gpu.read(), readback.read(), writer_.check_meter().read(),
          writer_.encode_meter().read()};
}

PipelineWindow LiveStats::window(Clock::time_point now) const {
  PipelineWindow w;
  const auto times = read();
  for (std::size_t i = 0; i < times.size(); ++i) w.stages.push_back(since(times[i], last_times_[i]));
  w.wall_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - last_).count();
  w.dropped = writer_.dropped() - last_dropped_;
  return w;
}

PipelineWindow LiveStats::totals(Clock::time_point now) const {
  PipelineWindow w;
  w.stages = read();
  w.wall_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - start_).count();
  w.dropped = writer_.dropped();
  return w;
}

void LiveStats::print_if_due(Clock::time_point now, std::ostream& log) {
  if (interval_ == Clock::duration::zero() || now - last_ < interval_) return;
  print(window(now), std::chrono::duration<double>(now - start_).count(), log);
  last_ = now;
  last_times_ = read();
  last_dropped_ = writer_.dropped();
}

void LiveStats::print(const PipelineWindow& w, double t, std::ostream& log) {
  char when[32];
  std::snprintf(when, sizeof when, "%.1f", t);
  log << "meter-view: stats " << when << " s: " << format_stage_shares(w) << "; " << find_bottleneck(w).text << "\n";
}

}  // namespace meter::runner
