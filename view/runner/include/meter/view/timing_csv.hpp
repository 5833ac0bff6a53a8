// --timing-csv: per-frame timing by stage. Header "frame,time_s,update_ms,submit_ms,
// gpu_readback_ms,drawn", one row per rendered frame; with the frame-rate governor on, its columns
// last (frames_csv.hpp: kGovernorColumns).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "meter/engine/renderer.hpp"
#include "meter/view/frames_csv.hpp"

namespace meter::view {

class TimingCsv {
 public:
  // An empty path: no file (row() does nothing). Throws ViewError when the file cannot be written.
  TimingCsv() = default;  // no file
  explicit TimingCsv(const std::string& path, bool governor = false);
  void row(std::uint64_t frame, double t, const engine::FrameTiming& timing, const GovernorCells* governor = nullptr);

 private:
  std::ofstream out_;
  bool governor_ = false;
};

}  // namespace meter::view
