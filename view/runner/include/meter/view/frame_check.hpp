// The per-frame check stage of the live pipeline: between readback and PNG encode, on the output
// thread, every read-back frame is handed to the check hook before it is (maybe) encoded.
//
// HOOK for a display integrity monitor: set `FrameCheckStage::check` (run_live's `check` argument)
// to a callable taking the frame's top-down RGBA pixels and its FrameInfo; set
// `every_drawn_frame` so that every drawn frame is read back, not only dumped ones. The callable
// runs on the output thread (not the GL thread): it must not touch GL, and what it reports to the
// render loop (faults for STATUS) it passes through something thread-safe. An exception from it
// is counted as a failed dump (logged, STATUS dump-failed). Its time is the "check" stage's busy
// time in --stats. The concurrent pipeline only: --pipeline sequential runs no check stage.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>

#include "meter/platform/image.hpp"

namespace meter::view {

struct FrameInfo {
  std::uint64_t frame = 0;     // 0-based live frame number (frames.csv frame)
  double t = 0.0;              // seconds on the view's clock (frames.csv time_s)
  bool drawn = false;          // false: the renderer skipped it (the image is the frame that stands)
  std::filesystem::path png;   // where it is written; empty: read back for the check only
  std::int64_t rendered_ns = 0;  // CLOCK_MONOTONIC when its GL work was done
};

using FrameCheck = std::function<void(const platform::Image& pixels, const FrameInfo& info)>;

struct FrameCheckStage {
  FrameCheck check;                // empty: no check stage work
  bool every_drawn_frame = false;  // read back every drawn frame for the check
};

// Reverses the row order in place (GL's bottom-up rows -> Image's top-down).
void flip_rows(platform::Image& image);

}  // namespace meter::view
