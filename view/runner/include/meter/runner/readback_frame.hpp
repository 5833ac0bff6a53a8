// A frame read back on the GL thread on its way to the writer thread: what travels with it (frame
// number, its time, where its PNG goes) and its pixels.
#pragma once

#include <cstdint>
#include <filesystem>

#include "meter/platform/image.hpp"

namespace meter::runner {

struct FrameInfo {
  std::uint64_t frame = 0;     // 0-based live frame number (frames.csv frame)
  double t = 0.0;              // seconds on the view's clock (frames.csv time_s)
  bool drawn = false;          // false: the renderer skipped it (the image is the frame that stands)
  std::filesystem::path png;   // where it is written
};

struct ReadbackFrame {
  FrameInfo info;
  platform::Image image;  // rows bottom-up as GL reads them, until the writer flips them (platform::flip_rows)
};

}  // namespace meter::runner
