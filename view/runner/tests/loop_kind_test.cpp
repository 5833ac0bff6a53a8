// The live loop's kind from --pipeline: each name, an unknown one, and the injected integrity fault,
// which only a loop completing each frame before the next can schedule: never silently another loop.
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

std::string refusal(const ViewOptions& o) {
  try {
    live_loop_kind(o);
  } catch (const ViewError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(LoopKind, EachPipelineNameIsItsLoop) {
  EXPECT_EQ(live_loop_kind(with("overlapped")), LoopKind::Overlapped);
  EXPECT_EQ(live_loop_kind(with("concurrent")), LoopKind::Concurrent);
  EXPECT_EQ(live_loop_kind(with("sequential")), LoopKind::Sequential);
  EXPECT_EQ(refusal(with("pipelined")), "--pipeline: expected overlapped, concurrent or sequential, got \"pipelined\"");
}

TEST(LoopKind, InjectedFaultRunsInTheLoopAskedFor) {
  EXPECT_EQ(live_loop_kind(with("concurrent", "stuck@45")), LoopKind::Concurrent);
  EXPECT_EQ(live_loop_kind(with("sequential", "stuck@45")), LoopKind::Sequential);
}

TEST(LoopKind, InjectedFaultInTheOverlappedLoopIsRefusedNotSwapped) {
  const std::string why = refusal(with("overlapped", "stuck@45"));
  EXPECT_NE(why.find("--inject-fault stuck@45"), std::string::npos) << why;
  EXPECT_NE(why.find("--pipeline concurrent"), std::string::npos) << why;
}

}  // namespace
}  // namespace meter::runner
