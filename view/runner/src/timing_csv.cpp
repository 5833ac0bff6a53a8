#include "meter/runner/timing_csv.hpp"

#include <iomanip>
#include <sstream>

#include "output_file.hpp"

namespace meter::runner {

TimingCsv::TimingCsv(const std::string& path, bool governor, bool presented) : governor_(governor) {
  if (path.empty()) return;
  out_ = create_output_file(path);
  out_ << "frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn";
  if (governor_) out_ << "," << kGovernorColumns;
  if (presented) {  // each row waits for its frame's presentation feedback
    set_holding();
    out_ << ",presented_ns,refresh_seq,to_presented_ms";
  }
  out_ << "\n" << std::flush;  // the columns on disk at once, before any row (rows may wait for the display)
}

void TimingCsv::row(std::uint64_t frame, double t, const engine::FrameTiming& timing, const GovernorCells* governor) {
  if (!out_.is_open()) return;
  cells(out_, frame, t, timing, governor);
  out_ << "\n";
}

void TimingCsv::cells(std::ostream& out, std::uint64_t frame, double t, const engine::FrameTiming& timing,
                      const GovernorCells* governor) const {
  out << frame << "," << std::fixed << std::setprecision(4) << t << "," << timing.update_ms << "," << timing.submit_ms
      << "," << timing.gpu_readback_ms << "," << timing.drawn;
  if (governor_) out << governor_cells_text(governor ? *governor : GovernorCells{});
}

void TimingCsv::on_frame(const engine::FrameRecord& frame) {
  if (!holding()) return row(frame.request.frame, frame.request.t, frame.timing, frame.governor);
  std::ostringstream text;
  cells(text, frame.request.frame, frame.request.t, frame.timing, frame.governor);
  hold(frame.request.frame, text.str(), frame.render_ended_ns);
}

PresentationRows::Write TimingCsv::writer() {
  return [this](const std::string& text, std::int64_t render_ended_ns, const platform::PresentedFrame* shown) {
    write(text, render_ended_ns, shown);
  };
}

void TimingCsv::write(const std::string& text, std::int64_t render_ended_ns, const platform::PresentedFrame* shown) {
  out_ << text << ",";
  if (shown)
    out_ << shown->presented_ns << "," << shown->sequence << "," << std::fixed << std::setprecision(3)
         << double(shown->presented_ns - render_ended_ns) / 1e6;
  else
    out_ << ",,";
  out_ << "\n";
}

}  // namespace meter::runner
