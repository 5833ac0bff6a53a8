// The view's faults as STATUS flags: held for the hold time after the last report, then cleared;
// counted; several faults at once; unknown bits kept.
#include "meter/runner/view_health.hpp"

#include <gtest/gtest.h>

#include "meter/protocol/wire.hpp"

namespace meter::runner {
namespace {

using namespace std::chrono_literals;
using protocol::kViewFaultDumpFailed;
using protocol::kViewFaultFrameDeadline;

TEST(ViewHealth, AFaultIsHeldForTheHoldTimeThenClears) {
  ViewHealth h;
  const auto t0 = ViewHealth::Clock::time_point{} + 10s;
  EXPECT_EQ(h.flags(t0), 0U);
  h.report(kViewFaultDumpFailed, t0);
  EXPECT_EQ(h.flags(t0), kViewFaultDumpFailed);
  EXPECT_EQ(h.flags(t0 + 999ms), kViewFaultDumpFailed) << "held for kViewFaultHoldMs (1000 ms)";
  EXPECT_EQ(h.flags(t0 + 1000ms), 0U) << "cleared once the hold time passed without the fault";
  h.report(kViewFaultFrameDeadline, t0 + 500ms);
  h.report(kViewFaultFrameDeadline, t0 + 1200ms);
  EXPECT_EQ(h.flags(t0 + 900ms), kViewFaultDumpFailed | kViewFaultFrameDeadline);
  EXPECT_EQ(h.flags(t0 + 2100ms), kViewFaultFrameDeadline) << "the hold runs from the last report";
  EXPECT_EQ(h.count(kViewFaultFrameDeadline), 2U);
  EXPECT_EQ(h.count(kViewFaultDumpFailed), 1U);
  h.report(1U << 20, t0 + 3s);
  EXPECT_EQ(h.flags(t0 + 3s), 1U << 20) << "a bit without a name is carried too";
  h.report(0, t0);  // no fault: nothing
  EXPECT_EQ(h.count(0), 0U);
}

TEST(ViewHealth, FaultNamesForTheLog) {
  EXPECT_EQ(protocol::describe_fault_flags(0), "none");
  EXPECT_EQ(protocol::describe_fault_flags(kViewFaultFrameDeadline | kViewFaultDumpFailed | (1U << 9)),
            "frame-deadline, dump-failed, bit 9");
  EXPECT_EQ(protocol::describe_fault_flags(protocol::kViewFaultIntegrity), "integrity");
  EXPECT_EQ(protocol::describe_fault_flags(protocol::kViewFaultDisplayFrozen), "display-frozen");
}

}  // namespace
}  // namespace meter::runner
