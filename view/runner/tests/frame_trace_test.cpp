// The trace-json slices of a frame, as the frame pipeline's sink writes them: evaluate and render
// from the record's stamps, the renderer's parts laid end to end inside render, the governor's
// slice only with its cells; an overrunning frame's ring written and logged.
#include "meter/runner/frame_trace.hpp"

#include <fstream>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/protocol/trace_events.hpp"
#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using ::testing::HasSubstr;

engine::FrameRecord traced_frame(std::int64_t began) {
  engine::FrameRecord r;
  r.request.frame = 7;
  r.timing.drawn = true;
  r.timing.update_ms = 1.0, r.timing.submit_ms = 2.0, r.timing.gpu_readback_ms = 3.0;
  r.evaluate_began_ns = began;
  r.render_began_ns = began + 1'000'000;
  r.render_ended_ns = began + 7'000'000;
  return r;
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(FrameTrace, SlicesOfAFrameFromItsRecord) {
  const auto dir = testing::scratch_dir();
  const auto file = dir / "trace.json";
  std::ostringstream log;
  {
    TraceEvents events(file.string(), 0.0, dir);
    FrameTrace sink(events, 0.0, log);
    sink.on_frame(traced_frame(1'000'000'000));
    engine::FrameRecord governed = traced_frame(2'000'000'000);
    engine::GovernorCells cells;
    cells.reduced = "BackPanel=gouraud/lod0";
    governed.governor = &cells;
    sink.on_frame(governed);
    ASSERT_TRUE(events.close());
  }
  const std::string doc = read_all(file);
  EXPECT_THAT(doc, HasSubstr("\"name\":\"evaluate\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1000000.000,\"dur\":1000.000"));
  EXPECT_THAT(doc, HasSubstr("\"name\":\"render\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1001000.000,\"dur\":6000.000"));
  // update, submit, readback end to end from the render's start.
  EXPECT_THAT(doc, HasSubstr("\"name\":\"update\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1001000.000,\"dur\":1000.000"));
  EXPECT_THAT(doc, HasSubstr("\"name\":\"submit\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1002000.000,\"dur\":2000.000"));
  EXPECT_THAT(doc, HasSubstr("\"name\":\"readback\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1004000.000,\"dur\":3000.000"));
  EXPECT_THAT(doc, HasSubstr("\"name\":\"governor BackPanel=gouraud/lod0\",\"cat\":\"governor\""));
  std::size_t governor_slices = 0;
  for (auto at = doc.find("\"cat\":\"governor\""); at != std::string::npos; at = doc.find("\"cat\":\"governor\"", at + 1))
    ++governor_slices;
  EXPECT_EQ(governor_slices, 1u) << "a governor slice only for the frame with governor cells";
  EXPECT_EQ(log.str(), "");
}

TEST(FrameTrace, AnOverrunningFrameIsLoggedWithItsFile) {
  const auto dir = testing::scratch_dir();
  std::ostringstream log;
  TraceEvents events("", 20.0, dir);
  FrameTrace sink(events, 20.0, log);
  // Began 30 ms ago: over the 20 ms threshold when the sink sees it.
  sink.on_frame(traced_frame(protocol::monotonic_now_ns() - 30'000'000));
  EXPECT_THAT(log.str(), HasSubstr("meter-view: frame 7 took "));
  EXPECT_THAT(log.str(), HasSubstr("(--trace-on-overrun 20): the last seconds of trace in " + (dir / "overrun_000007.json").string()));
}

}  // namespace
}  // namespace meter::runner
