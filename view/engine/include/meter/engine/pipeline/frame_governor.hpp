// The frame pipeline's quality input (docs/uniform-frame-rate.md): asked once per frame with the
// frame's planned load, between planning and drawing; its choice goes down to the renderer as a
// plain value. The frame-rate governor of meter-view's live and play modes implements it.
#pragma once

#include <cstdint>
#include <cstddef>
#include <optional>
#include <string>

#include "meter/engine/governor/quality_choice.hpp"
#include "meter/engine/renderer.hpp"

namespace meter::engine {

// What the governor did on the last frame: its prediction, the measured time, the choice (the
// frames.csv, timing CSV and trace cells).
struct GovernorCells {
  double predicted_ms = 0.0, measured_ms = 0.0;
  std::size_t units_reduced = 0;
  int msaa = 0;
  float scale = 1.0f;
  std::string reduced;
};

class FrameGovernor {
 public:
  virtual ~FrameGovernor() = default;
  // The quality to draw the planned frame at; nullopt keeps the current one.
  virtual std::optional<governor::QualityChoice> choose(const governor::FrameLoad& planned) = 0;
  // The frame was drawn (or skipped): `began_ns` is when it began to be planned (CLOCK_MONOTONIC,
  // protocol::monotonic_now_ns(), the clock of std::chrono::steady_clock).
  virtual void rendered(const FrameTiming& timing, std::int64_t began_ns) = 0;
  // The last frame's cells; nullptr when no governor runs.
  virtual const GovernorCells* cells() const = 0;
};

}  // namespace meter::engine
