// --timing-csv: per-frame timing by stage. Header "frame,time_s,update_ms,submit_ms,
// gpu_readback_ms,drawn", one row per rendered frame.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "meter/engine/renderer.hpp"

namespace meter::view {

class TimingCsv {
 public:
  // An empty path: no file (row() does nothing). Throws ViewError when the file cannot be written.
  TimingCsv() = default;  // no file
  explicit TimingCsv(const std::string& path);
  void row(std::uint64_t frame, double t, const engine::FrameTiming& timing);

 private:
  std::ofstream out_;
};

}  // namespace meter::view
