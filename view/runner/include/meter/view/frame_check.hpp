// What travels with a read-back frame from the GL thread to the writer thread (frame number, its
// time, where its PNG goes), and the row flip the writer does first (GL reads rows bottom-up).
#pragma once

#include <cstdint>
#include <filesystem>

#include "meter/platform/image.hpp"

namespace meter::view {

struct FrameInfo {
  std::uint64_t frame = 0;     // 0-based live frame number (frames.csv frame)
  double t = 0.0;              // seconds on the view's clock (frames.csv time_s)
  bool drawn = false;          // false: the renderer skipped it (the image is the frame that stands)
  std::filesystem::path png;   // where it is written
};

// Reverses the row order in place (GL's bottom-up rows -> Image's top-down).
void flip_rows(platform::Image& image);

}  // namespace meter::view
