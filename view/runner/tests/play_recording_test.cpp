// The simulated clock of --play: frame times are exact multiples of 1/fps over the recording's
// span, and the span runs from the first to the last signal update (HELLO, HEARTBEAT and STATUS
// lines do not count). Pure functions, no GL.
#include <gtest/gtest.h>

#include <sstream>

#include "meter/runner/play_recording.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

TEST(PlayFrameTimes, ExactMultiplesOfTheFramePeriodOverTheSpan) {
  const auto t = play_frame_times(10.0, 60.0);
  ASSERT_EQ(t.size(), 601u);  // 0, 0.1, ..., 60.0: both ends drawn
  EXPECT_EQ(t[0], 0.0);
  EXPECT_EQ(t[3], 3.0 / 10.0);  // k / fps, not a running sum of 0.1 (which gives 0.30000000000000004)
  EXPECT_EQ(t[600], 60.0);
}

TEST(PlayFrameTimes, AZeroSpanStillDrawsOneFrameAndABadRateIsRefused) {
  EXPECT_EQ(play_frame_times(30.0, 0.0).size(), 1u);
  EXPECT_EQ(play_frame_times(30.0, 0.05).size(), 2u);  // 0 and 1/30
  EXPECT_THROW(play_frame_times(0.0, 1.0), ViewError);
  EXPECT_THROW(play_frame_times(10.0, -1.0), ViewError);
}

TEST(PlaySpan, FromTheFirstToTheLastSignalUpdate) {
  std::istringstream in(
      "# meter-link-recording/1 catalog=0x0\n"
      "(1.000000000) HEARTBEAT seq=1 sent=1.000000000\n"
      "(2.000000000) SNAPSHOT seq=2 sent=2.000000000 complete=1 Vehicle.Speed=0:valid\n"
      "(2.500000000) DELTA seq=3 sent=2.500000000 Vehicle.Speed=12.5:valid\n"
      "(9.000000000) STATUS seq=4 sent=9.000000000 frames=1 last_seq=0 faults=0x00000000\n");
  const auto frames = protocol::parse_recording(in, "rec.txt");
  const auto span = play_span(frames, "rec.txt");
  EXPECT_EQ(span.first_ns, 2'000'000'000);
  EXPECT_DOUBLE_EQ(span.span_s, 0.5);
}

TEST(PlaySpan, ARecordingWithoutUpdatesIsNamed) {
  std::istringstream in("(1.000000000) HEARTBEAT seq=1 sent=1.000000000\n");
  const auto frames = protocol::parse_recording(in, "idle.rec");
  try {
    play_span(frames, "idle.rec");
    FAIL() << "expected a ViewError";
  } catch (const ViewError& e) {
    EXPECT_NE(std::string(e.what()).find("idle.rec: the recording holds no SNAPSHOT or DELTA"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace meter::runner
