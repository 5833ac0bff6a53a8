// --timing-csv: per-frame timing by stage. Header "frame,time_s,update_ms,submit_ms,
// gpu_readback_ms,drawn", one row per rendered frame; with the frame-rate governor on, its columns
// next (frames_csv.hpp: kGovernorColumns); with a display (--output),
// "presented_ns,refresh_seq,to_presented_ms" last: when the frame turned into light
// (CLOCK_MONOTONIC, the compositor's presentation feedback), the output's refresh counter then, and
// how long after its render ended; all empty for a frame never shown (skipped, or replaced
// before a refresh). Such rows are written once their frame's fate is known, or after at most
// PresentationRows::kHoldNs without it.
#pragma once

#include <cstdint>
#include <fstream>
#include <ostream>
#include <string>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/runner/frames_csv.hpp"
#include "meter/runner/presentation_rows.hpp"

namespace meter::runner {

// A frame sink: one row per frame the pipeline renders.
class TimingCsv : public engine::FrameSink, public PresentationHeldCsv {
 public:
  // An empty path: no file (row() does nothing). Throws ViewError when the file cannot be written.
  // `presented`: a display shows the frames; its columns are in the header and each row waits for
  // its frame's presentation feedback.
  TimingCsv() = default;  // no file
  explicit TimingCsv(const std::string& path, bool governor = false, bool presented = false);
  void row(std::uint64_t frame, double t, const engine::FrameTiming& timing, const GovernorCells* governor = nullptr);
  void on_frame(const engine::FrameRecord& frame) override;

 private:
  void cells(std::ostream& out, std::uint64_t frame, double t, const engine::FrameTiming& timing,
             const GovernorCells* governor) const;
  // A row released for the display's news: `text` and the display's cells.
  void write(const std::string& text, std::int64_t render_ended_ns, const platform::PresentedFrame* shown);
  PresentationRows::Write writer() override;

  std::ofstream out_;
  bool governor_ = false;
};

}  // namespace meter::runner
