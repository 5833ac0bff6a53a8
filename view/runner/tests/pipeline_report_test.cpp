// --stats: stage shares and the bottleneck named by CUBE's rule, on synthetic windows.
#include "meter/runner/pipeline_report.hpp"

#include <gtest/gtest.h>

namespace meter::runner {
namespace {

constexpr std::int64_t kMs = 1'000'000;

StageTimes stage(const char* name, int lane, int busy, int in, int out, std::uint64_t items = 10) {
  return StageTimes{name, lane, busy * kMs, in * kMs, out * kMs, items};
}

// A 1000 ms window: the percents below are the milliseconds given.
PipelineWindow window(std::vector<StageTimes> stages, std::uint64_t dropped = 0) {
  return PipelineWindow{std::move(stages), 1000 * kMs, dropped};
}

TEST(PipelineReport, ASlowEncoderThatTheRenderLoopWaitsOnIsTheBottleneck) {
  const auto w = window({stage("intake", 1, 10, 5, 0), stage("render", 1, 300, 0, 0), stage("readback", 1, 50, 0, 410),
                         stage("check", 2, 10, 0, 0), stage("encode", 2, 620, 0, 0)});
  const auto b = find_bottleneck(w);
  EXPECT_EQ(b.stage, "encode");
  EXPECT_EQ(b.text, "encode busy 62 % (its thread 63 %), readback waited 41 % on it: encode is the bottleneck");
}

TEST(PipelineReport, ARenderBoundLoopNamesRenderAndTheStarvedWriter) {
  const auto w = window({stage("intake", 1, 20, 10, 0), stage("evaluate", 1, 50, 0, 0), stage("render", 1, 800, 0, 0),
                         stage("readback", 1, 60, 0, 0), stage("check", 2, 5, 700, 0), stage("encode", 2, 200, 0, 0)});
  const auto b = find_bottleneck(w);
  EXPECT_EQ(b.stage, "render");
  EXPECT_EQ(b.text,
            "render busy 80 % (its thread 93 %), check waited 70 % for its output: render is the bottleneck")
      << "render's producer shares its thread, so the downstream wait is quoted";
}

// The overlapped loop's eight stages (the GPU a lane of its own after render) over 1000 ms, with
// the given busy times and render's wait for output space (for the frame still executing).
PipelineWindow overlapped(int evaluate, int render_waits, int gpu, int readback, int check_waits) {
  return window({stage("intake", 1, 5, 0, 0), stage("evaluate", 1, evaluate, 0, 0), stage("plan", 1, 10, 0, 0),
                 stage("render", 1, 30, 0, render_waits), stage("gpu", 3, gpu, 0, 0), stage("readback", 1, readback, 0, 0),
                 stage("check", 2, 2, check_waits, 0), stage("encode", 2, 50, 0, 0)});
}

// Render waiting for a frame still executing is a wait for output space, so the GPU is named, as
// CUBE named scan conversion.
TEST(PipelineReport, ARenderStageWaitingOnTheGpuNamesTheGpu) {
  const Bottleneck b = find_bottleneck(overlapped(20, 800, 880, 0, 990));
  EXPECT_EQ(b.stage, "gpu");
  EXPECT_EQ(b.text, "gpu busy 88 %, render waited 80 % on it: gpu is the bottleneck");
  // Render held back by the GPU is not held back by a busier PNG writer further on.
  PipelineWindow w = overlapped(20, 110, 140, 70, 400);
  w.stages.back().busy_ns = 560 * kMs;
  EXPECT_EQ(find_bottleneck(w).text, "gpu busy 14 %, render waited 11 % on it: gpu is the bottleneck");
}

// A saturated CPU stage with the GPU after it: the GPU, never waiting for the loop, is not quoted
// as waiting for the stage's output; nor is a stage upstream that never waited on it.
TEST(PipelineReport, ASlowCpuStageBeforeTheGpuQuotesNoIdleWait) {
  EXPECT_EQ(find_bottleneck(overlapped(850, 0, 40, 60, 900)).text,
            "evaluate busy 85 % (its thread 96 %), check waited 90 % for its output: evaluate is the bottleneck");
  EXPECT_EQ(find_bottleneck(overlapped(25, 0, 40, 800, 0)).text,
            "readback busy 80 % (its thread 87 %): readback is the bottleneck");
}

TEST(PipelineReport, AClockPacedPipelineHasNoBottleneck) {
  const auto w = window({stage("intake", 1, 5, 850, 0), stage("render", 1, 90, 0, 0), stage("check", 2, 1, 900, 0),
                         stage("encode", 2, 60, 0, 0)});
  const auto b = find_bottleneck(w);
  EXPECT_TRUE(b.stage.empty());
  EXPECT_EQ(b.text, "no bottleneck: intake waited 85 % for input (the frame clock, the link), busiest render 9 %");
}

TEST(PipelineReport, DroppedFramesNameTheBottleneckEvenBelowSaturation) {
  // The writer is busy 60 % yet refuses frames: it is behind in bursts and the render loop, under
  // --dump-policy drop, never waited on it.
  const auto w = window({stage("render", 1, 100, 0, 0), stage("readback", 1, 20, 0, 0), stage("encode", 2, 600, 0, 0)}, 12);
  const auto b = find_bottleneck(w);
  EXPECT_EQ(b.stage, "encode");
  EXPECT_EQ(b.text, "encode busy 60 %, readback waited 0 % on it, 12 frames dropped: encode is the bottleneck");
}

TEST(PipelineReport, SharesAreWholePercentsCappedAtTheWindow) {
  const auto w = window({stage("render", 1, 333, 1, 0, 20), stage("encode", 2, 1040, 0, 0, 3)});
  EXPECT_EQ(format_stage_shares(w),
            "render busy 33 % in 0 % out 0 % (20) | encode busy 100 % in 0 % out 0 % (3)")
      << "an encode ending in this window but begun in the previous one is not shown above 100 %";
}

TEST(PipelineReport, AnEmptyWindowNamesNothing) {
  EXPECT_TRUE(find_bottleneck(PipelineWindow{}).text.empty());
  EXPECT_TRUE(find_bottleneck(PipelineWindow{{stage("render", 1, 1, 0, 0)}, 0, 0}).stage.empty());
}

TEST(StageMeter, ReadsAndDifferencesItsCounters) {
  StageMeter m("render", 1);
  m.busy(5);
  m.waited_input(3);
  m.waited_output(2);
  m.item();
  const StageTimes a = m.read();
  m.busy(10);
  m.item();
  const StageTimes d = since(m.read(), a);
  EXPECT_EQ(d.name, "render");
  EXPECT_EQ(d.lane, 1);
  EXPECT_EQ(d.busy_ns, 10);
  EXPECT_EQ(d.wait_in_ns, 0);
  EXPECT_EQ(d.items, 1U);
  EXPECT_EQ(a.wait_out_ns, 2);
}

}  // namespace
}  // namespace meter::runner
