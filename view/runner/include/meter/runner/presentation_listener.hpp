// What hears of the display's presentation feedback (display_sink.hpp): the sinks that put the
// time a frame turned into light beside their rows.
#pragma once

#include "meter/platform/display.hpp"

namespace meter::runner {

// Told when a frame was presented (CLOCK_MONOTONIC), in presentation order, when a frame was not
// given to the display at all, and when no more will
// come (the mode ended and the last feedback arrived or timed out).
class PresentationListener {
 public:
  virtual ~PresentationListener() = default;
  virtual void on_presented(const platform::PresentedFrame& shown) = 0;
  // Frame `frame` was not handed to the display (it wrote no pixel): the screen keeps the one before.
  virtual void not_presented(std::uint64_t /*frame*/) {}
  virtual void presentation_done() {}
};

}  // namespace meter::runner
