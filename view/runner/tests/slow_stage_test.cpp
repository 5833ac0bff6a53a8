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
  struct Case {
    const char* text;
    bool overlapped;
    const char* says;
  };
  const Case cases[] = {
      {"encode", true, "expected STAGE:MS"},
      {"gpu:5", true, "unknown stage \"gpu\" (expected one of intake, evaluate"},
      {"encode:fast", true, "\"fast\" is not a delay in milliseconds"},
      {"encode:0", true, "not a delay"},
      {"encode:-3", true, "not a delay"},
      {"encode:5000", true, "(0, 1000]"},
      {"encode:nan", true, "not a delay"},
      // Plan and render are inside the engine's one render call outside the overlapped loop.
      {"plan:5", false, "use --pipeline overlapped"},
      {"intake:5", false, "accepted"},
  };
  for (const Case& c : cases) EXPECT_NE(refusal(c.text, c.overlapped).find(c.says), std::string::npos) << c.text;
}

}  // namespace
}  // namespace meter::runner
