// --timing-csv: per-frame timing by stage. Header "frame,time_s,update_ms,submit_ms,
// gpu_readback_ms,drawn", one row per rendered frame; with the frame-rate governor on, its columns
// last (frames_csv.hpp: kGovernorColumns).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/runner/frames_csv.hpp"

namespace meter::runner {

// A frame sink: one row per frame the pipeline renders.
class TimingCsv : public engine::FrameSink {
 public:
  // An empty path: no file (row() does nothing). Throws ViewError when the file cannot be written.
  TimingCsv() = default;  // no file
  explicit TimingCsv(const std::string& path, bool governor = false);
  void row(std::uint64_t frame, double t, const engine::FrameTiming& timing, const GovernorCells* governor = nullptr);
  void on_frame(const engine::FrameRecord& frame) override {
    row(frame.request.frame, frame.request.t, frame.timing, frame.governor);
  }

 private:
  std::ofstream out_;
  bool governor_ = false;
};

}  // namespace meter::runner
