// Rows held for their frame's presentation feedback (frames.csv and the timing CSV with a display):
// written in the order added, each once its frame's fate is known or after the hold time.
#include "meter/runner/presentation_rows.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace meter::runner {
namespace {

struct Written {
  std::vector<std::string> rows;
  PresentationRows::Write write() {
    return [this](const std::string& text, std::int64_t, const platform::PresentedFrame* shown) {
      rows.push_back(text + (shown ? "@" + std::to_string(shown->presented_ns) : "@-"));
    };
  }
};

platform::PresentedFrame shown(std::uint64_t frame, std::int64_t at_ns, bool discarded = false) {
  platform::PresentedFrame f;
  f.frame = frame;
  f.presented_ns = at_ns;
  f.discarded = discarded;
  return f;
}

TEST(PresentationRows, ARowWaitsForItsFramesFeedbackAndRowsKeepTheirOrder) {
  Written out;
  PresentationRows rows;
  rows.add(1, "a", 0, 0, out.write());
  rows.add(2, "b", 0, 0, out.write());
  rows.not_presented(2, 1, out.write());  // 2 drew nothing: known, but behind 1
  EXPECT_TRUE(out.rows.empty());
  EXPECT_EQ(rows.held(), 2u);
  rows.presented(shown(1, 500), 2, out.write());
  EXPECT_EQ(out.rows, (std::vector<std::string>{"a@500", "b@-"}));
}

TEST(PresentationRows, FeedbackOfALaterFrameTellsTheEarlierOnesWereNotShown) {
  Written out;
  PresentationRows rows;
  rows.add(3, "c", 0, 0, out.write());
  rows.add(4, "d", 0, 0, out.write());
  rows.add(5, "e", 0, 0, out.write());
  rows.presented(shown(4, 700, /*discarded=*/true), 1, out.write());
  EXPECT_EQ(out.rows, (std::vector<std::string>{"c@-", "d@-"})) << "3 never reached the display, 4 was replaced";
  rows.presented(shown(5, 900), 2, out.write());
  EXPECT_EQ(out.rows.back(), "e@900");
}

TEST(PresentationRows, ARowAddedAfterItsFeedbackIsWrittenAtOnceWithIt) {
  // A dumped frame's row comes once its read finished, which can be after the feedback.
  Written out;
  PresentationRows rows;
  rows.presented(shown(7, 1234), 0, out.write());
  rows.not_presented(8, 0, out.write());
  rows.add(6, "f", 0, 1, out.write());
  rows.add(7, "g", 0, 1, out.write());
  rows.add(8, "h", 0, 1, out.write());
  EXPECT_EQ(out.rows, (std::vector<std::string>{"f@-", "g@1234", "h@-"}));
}

TEST(PresentationRows, ARowWaitsAtMostTheHoldTime) {
  Written out;
  PresentationRows rows(1000);
  rows.add(1, "a", 0, 0, out.write());
  rows.add(2, "b", 0, 600, out.write());
  EXPECT_TRUE(out.rows.empty());
  rows.add(3, "c", 0, 1000, out.write());  // a held 1000: out without feedback; b not yet
  EXPECT_EQ(out.rows, (std::vector<std::string>{"a@-"}));
  rows.presented(shown(2, 42), 1100, out.write());
  EXPECT_EQ(out.rows, (std::vector<std::string>{"a@-", "b@42"}));
  rows.done(out.write());
  rows.add(4, "d", 0, 1200, out.write());  // after done: at once
  EXPECT_EQ(out.rows, (std::vector<std::string>{"a@-", "b@42", "c@-", "d@-"}));
}

}  // namespace
}  // namespace meter::runner
