#include "meter/runner/timing_csv.hpp"

#include <iomanip>

#include "output_file.hpp"

namespace meter::runner {

TimingCsv::TimingCsv(const std::string& path, bool governor) : governor_(governor) {
  if (path.empty()) return;
  out_ = create_output_file(path);
  out_ << "frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn";
  if (governor_) out_ << "," << kGovernorColumns;
  out_ << "\n";
}

void TimingCsv::row(std::uint64_t frame, double t, const engine::FrameTiming& timing, const GovernorCells* governor) {
  if (!out_.is_open()) return;
  out_ << frame << "," << std::fixed << std::setprecision(4) << t << "," << timing.update_ms << "," << timing.submit_ms
       << "," << timing.gpu_readback_ms << "," << timing.drawn;
  if (governor_) out_ << governor_cells_text(governor ? *governor : GovernorCells{});
  out_ << "\n";
}

}  // namespace meter::runner
