// The test-only slow stage (--inject-slow-stage STAGE:MS): what it accepts, what it refuses and why.
#include <gtest/gtest.h>

#include "meter/runner/slow_stage.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

std::string refusal(const std::string& text, bool overlapped = true) {
  try {
    parse_slow_stage(text, overlapped);
  } catch (const ViewError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(SlowStage, EveryStageNamedWithItsDelay) {
  for (auto stage : kSlowableStages) {
    const SlowStage s = parse_slow_stage(std::string(stage) + ":2.5", true);
    EXPECT_EQ(s.stage, stage);
    EXPECT_EQ(s.delay, std::chrono::microseconds(2500));
    EXPECT_EQ(s.of(stage), std::chrono::microseconds(2500));
    EXPECT_EQ(s.of("gpu"), std::chrono::nanoseconds(0));
  }
  EXPECT_TRUE(parse_slow_stage("", false).stage.empty());
}

TEST(SlowStage, BadTextIsRefusedNamingWhatWasExpected) {
  EXPECT_NE(refusal("encode").find("expected STAGE:MS"), std::string::npos);
  EXPECT_NE(refusal("gpu:5").find("unknown stage \"gpu\" (expected one of intake, evaluate"), std::string::npos);
  EXPECT_NE(refusal("encode:fast").find("\"fast\" is not a delay in milliseconds"), std::string::npos);
  EXPECT_NE(refusal("encode:0").find("not a delay"), std::string::npos);
  EXPECT_NE(refusal("encode:-3").find("not a delay"), std::string::npos);
  EXPECT_NE(refusal("encode:5000").find("(0, 1000]"), std::string::npos);
  EXPECT_NE(refusal("encode:nan").find("not a delay"), std::string::npos);
  // Plan and render are inside the engine's one render call outside the overlapped loop.
  EXPECT_NE(refusal("plan:5", false).find("use --pipeline overlapped"), std::string::npos);
  EXPECT_EQ(refusal("intake:5", false), "accepted");
}

}  // namespace
}  // namespace meter::runner
