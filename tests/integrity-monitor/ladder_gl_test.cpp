// Zero false alarms in process, quickly: the cluster swept over its dials (every needle from its
// start to full scale in tenths, telltales switching on and off as the booleans they are) on
// both backends at every MSAA rung meter-view selects. The full log replays (replay_test.cpp)
// are the drive-shaped check; this one covers the whole scale of every dial.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "monitor_rig.hpp"

using meter::platform::BackendKind;
using meter::testing::MonitorRig;

namespace {

class LadderSweep : public ::testing::TestWithParam<std::tuple<BackendKind, int>> {};

TEST_P(LadderSweep, EveryDialPositionAndLampStateRaisesNoAlarm) {
  const auto [backend, msaa] = GetParam();
  MonitorRig rig(meter::testing::converted_cluster(), backend, msaa);
  ASSERT_TRUE(rig.monitor->on()) << rig.monitor->off_reason();
  for (int k = 0; k <= 10; ++k) {
    auto state = rig.at(k / 10.0);
    for (const auto& r : rig.scene.integrity.regions)
      if (r.kind == meter::bridge::SafetyKind::Telltale) MonitorRig::set(state, r.signal, k % 2 ? 1.0 : 0.0);
    for (const auto& x : rig.frame(state)) ADD_FAILURE() << "step " << k << ": " << x.describe();
  }
  EXPECT_EQ(rig.monitor->frames_checked(), 11u);
}

INSTANTIATE_TEST_SUITE_P(Rungs, LadderSweep,
                         ::testing::Combine(::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                                            ::testing::Values(1, 2, 4)),
                         [](const auto& info) {
                           return std::string(meter::platform::to_string(std::get<0>(info.param))) + "_msaa" +
                                  std::to_string(std::get<1>(info.param));
                         });

}  // namespace
