// The live loop's kind from --pipeline: each name, an unknown one, and the injected integrity fault,
// which only a loop completing each frame before the next can schedule: never silently another loop.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/runner/loop_kind.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

ViewOptions with(const std::string& pipeline, const std::string& fault = "") {
  ViewOptions o;
  o.pipeline = pipeline;
  o.inject_fault = fault;
  return o;
}

// The call `live_loop_kind(o)` throws a ViewError whose message holds `text`.
auto refused_with(const std::string& text) { return ::testing::ThrowsMessage<ViewError>(::testing::HasSubstr(text)); }

TEST(LoopKind, EachPipelineNameIsItsLoop) {
  EXPECT_EQ(live_loop_kind(with("overlapped")), LoopKind::Overlapped);
  EXPECT_EQ(live_loop_kind(with("concurrent")), LoopKind::Concurrent);
  EXPECT_EQ(live_loop_kind(with("sequential")), LoopKind::Sequential);
  EXPECT_THAT([] { live_loop_kind(with("pipelined")); },
              refused_with("--pipeline: expected overlapped, concurrent or sequential, got \"pipelined\""));
}

TEST(LoopKind, InjectedFaultRunsInTheLoopAskedFor) {
  EXPECT_EQ(live_loop_kind(with("concurrent", "stuck@45")), LoopKind::Concurrent);
  EXPECT_EQ(live_loop_kind(with("sequential", "stuck@45")), LoopKind::Sequential);
}

TEST(LoopKind, InjectedFaultInTheOverlappedLoopIsRefusedNotSwapped) {
  const auto overlapped = [] { live_loop_kind(with("overlapped", "stuck@45")); };
  EXPECT_THAT(overlapped, refused_with("--inject-fault stuck@45"));
  EXPECT_THAT(overlapped, refused_with("--pipeline concurrent"));
}

}  // namespace
}  // namespace meter::runner
