// The live loop's pacing on a display (--latch): with callback, a due frame is drawn as soon as
// the display took the frame before (its frame callback or page flip); with late, it is drawn at
// the last safe moment before the display's next latch (LatchSchedule: the latch predicted from the
// display's latch times and the presentation feedback, less a high percentile of the recent renders
// and an adaptive margin), and shown at once. It hears the presentation feedback as a listener of
// the display's sink.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>

#include "meter/platform/display.hpp"
#include "meter/runner/latch_schedule.hpp"
#include "meter/runner/presentation_listener.hpp"

namespace meter::runner {

class DisplayLatch final : public PresentationListener {
 public:
  DisplayLatch(const platform::DisplayBackend& display, LatchPacing pacing);

  bool late() const { return pacing_ == LatchPacing::Late; }
  // Once the display took the frame before: how long the due frame still waits (ns; <= 0: draw
  // now). The first call after a frame decides for it; the decision holds until starting().
  std::int64_t wait_left_ns(std::int64_t now_ns);
  // The due frame starts (its link drained, evaluated, planned, drawn, shown) at now_ns. Returns
  // the latch it is drawn for (0: none).
  std::int64_t starting(std::int64_t now_ns);
  // After the frame started last completed: `shown` when it was handed to the display (at now_ns).
  void drawn(std::uint64_t frame, bool shown, std::int64_t now_ns);

  void on_presented(const platform::PresentedFrame& shown) override;
  // One line at exit: the pacing, frames drawn for a latch and missed, the fallbacks by reason,
  // the margin and render estimate it ended with.
  void summary(std::ostream& log) const;

 private:
  const platform::DisplayBackend& display_;
  const LatchPacing pacing_;
  LatchSchedule schedule_;
  std::optional<LatchDecision> decision_;
  LatchDecision started_;  // the decision of the frame started last
  std::int64_t start_ns_ = 0;
  std::array<std::uint64_t, 6> reasons_{};  // frames started, by LatchReason
};

}  // namespace meter::runner
