// Rows of a CSV that end in the time their frame was presented (frames.csv, the timing CSV with a
// display): a row is held until its frame's fate is known (presented, discarded, or never handed to
// the display) or for at most a bounded time, then written, always in the order the rows were
// added. Pure: the caller passes the time and writes the released rows.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "meter/platform/display.hpp"
#include "meter/runner/presentation_listener.hpp"

namespace meter::runner {

class PresentationRows {
 public:
  // A released row: its text (up to the display's cells), the time its render ended, and its
  // frame's presentation (nullptr: not shown, its feedback never came in time, or discarded).
  using Write = std::function<void(const std::string& text, std::int64_t render_ended_ns,
                                   const platform::PresentedFrame* shown)>;
  // `hold_ns`: the longest a row waits for its frame's feedback (CLOCK_MONOTONIC nanoseconds).
  explicit PresentationRows(std::int64_t hold_ns = kHoldNs) : hold_ns_(hold_ns) {}

  // Each call writes, through `write`, the rows it released (rows held longer than the hold time
  // go without a presentation).
  // Frame `frame`'s row; written at once when its frame's fate is known already.
  void add(std::uint64_t frame, std::string text, std::int64_t render_ended_ns, std::int64_t now_ns,
           const Write& write);
  // The feedback of a presented (or discarded) frame: every frame before it had its fate told
  // (feedback comes in presentation order, frames are presented in frame order).
  void presented(const platform::PresentedFrame& shown, std::int64_t now_ns, const Write& write);
  // The display was not given frame `frame` (it drew nothing new): the screen keeps the frame before.
  void not_presented(std::uint64_t frame, std::int64_t now_ns, const Write& write);
  // No more feedback will come: every row is written, and rows added after are written at once.
  void done(const Write& write);
  std::size_t held() const { return rows_.size(); }

  static constexpr std::int64_t kHoldNs = 1'000'000'000;  // the display's own stall wait

 private:
  struct Row {
    std::uint64_t frame;
    std::string text;
    std::int64_t render_ended_ns, added_ns;
    bool known = false;
    std::optional<platform::PresentedFrame> shown;
  };
  // The fate of `frame` when known: set, with the feedback when it was shown.
  bool fate(std::uint64_t frame, std::optional<platform::PresentedFrame>& shown) const;
  void tell(std::uint64_t frame, const std::optional<platform::PresentedFrame>& shown, std::int64_t now_ns,
            const Write& write);
  void expire(std::int64_t now_ns);
  void release(const Write& write);

  std::int64_t hold_ns_;
  std::deque<Row> rows_;
  // Fates told for frames whose rows may still come (a dumped frame's row is added once its read
  // finished, which can be after its feedback): the latest kFates of them.
  std::map<std::uint64_t, std::optional<platform::PresentedFrame>> fates_;
  std::optional<std::uint64_t> through_;  // every frame up to this one had its fate told
  bool done_ = false;
  static constexpr std::size_t kFates = 256;
};

// The listener side of a CSV whose rows wait for the display (frames.csv, the timing CSV): once
// holding() is set, rows go through hold() and the display's news releases them through writer().
class PresentationHeldCsv : public PresentationListener {
 public:
  void on_presented(const platform::PresentedFrame& shown) override;
  void not_presented(std::uint64_t frame) override;
  void presentation_done() override;

 protected:
  bool holding() const { return holding_; }
  void set_holding() { holding_ = true; }
  void hold(std::uint64_t frame, std::string text, std::int64_t render_ended_ns);
  virtual PresentationRows::Write writer() = 0;

 private:
  bool holding_ = false;
  PresentationRows rows_;
};

}  // namespace meter::runner
