// Each injected display fault is caught by the integrity monitor within 2 frames, on both
// backends, and the frames before it raise nothing (docs/integrity.md, "The monitor in
// meter-view"). In process, frame by frame: the cluster at 1280x480 MSAA 4, the fault put into
// the renderer's GL execution (engine/integrity/fault_injection.hpp), the monitor's own verdict.
#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>

#include "monitor_rig.hpp"

namespace fs = std::filesystem;
using meter::bridge::SafetyKind;
using meter::engine::FaultInjection;
using meter::engine::FaultKind;
using meter::platform::BackendKind;
using meter::testing::MonitorRig;

namespace {

struct Case {
  FaultKind kind;
  SafetyKind target;  // the kind of region it is put on (StuckFrame: none)
};

std::string param_name(const ::testing::TestParamInfo<std::tuple<BackendKind, Case>>& info) {
  return std::string(meter::platform::to_string(std::get<0>(info.param))) + "_" +
         meter::engine::fault_kind_name(std::get<1>(info.param).kind);
}

class Detection : public ::testing::TestWithParam<std::tuple<BackendKind, Case>> {};

// The detection latency in frames: 1 = caught in the first frame drawn with the fault.
constexpr int kMaxLatency = 2;
constexpr int kCleanFrames = 4;

TEST_P(Detection, CaughtWithinTwoFramesWithoutAnEarlierAlarm) {
  const auto [backend, c] = GetParam();
  MonitorRig rig(meter::testing::converted_cluster(), backend, 4);
  ASSERT_TRUE(rig.monitor->on()) << rig.monitor->off_reason();
  const meter::bridge::SafetyRegion* region = nullptr;
  FaultInjection fault;
  fault.kind = c.kind;
  if (c.kind != FaultKind::StuckFrame) {
    region = meter::testing::first_region(rig.scene.integrity, c.target);
    ASSERT_NE(region, nullptr) << "the cluster has no safety region of kind " << meter::bridge::to_string(c.target);
    fault.node = rig.scene.find_node(region->node);
    ASSERT_GE(fault.node, 0) << region->node;
    fault.box = {region->rect.x, rig.renderer->height() - region->rect.y - region->rect.height, region->rect.width,
                 region->rect.height};
  }
  // Rest: every needle at its dial's start (the speed needle at 0 or 26 km/h in turn), every
  // telltale dark. Then the state every item must show differently (needles at full scale,
  // telltales lit) arrives in the frame the fault starts.
  const auto rest = rig.at(0.0), moved = rig.at(1.0);
  auto rolling = rest;
  MonitorRig::set(rolling, "Vehicle.Speed", 26.0);
  for (int f = 0; f < kCleanFrames; ++f) {
    const auto faults = rig.frame(f % 2 ? rolling : rest);
    for (const auto& x : faults) ADD_FAILURE() << "false alarm at clean frame " << f << ": " << x.describe();
  }
  rig.frame(rest);
  rig.renderer->inject(fault);
  std::optional<int> caught;
  std::string seen;
  for (int k = 1; k <= 4 && !caught; ++k) {
    for (const auto& x : rig.frame(moved)) {
      if (region && x.region != region->name) continue;
      caught = k;
      seen = x.describe();
      break;
    }
  }
  ASSERT_TRUE(caught.has_value()) << meter::engine::fault_kind_name(c.kind) << " never caught";
  EXPECT_LE(*caught, kMaxLatency) << seen;
  // The latency table of docs/integrity.md is printed from here.
  std::printf("LATENCY %s %s %d frame(s): %s\n", meter::platform::to_string(backend).data(),
              meter::engine::fault_kind_name(c.kind), *caught, seen.c_str());
  // The fault ends: the safe path's full redraw gives the right image back, no alarm stays.
  rig.renderer->inject(std::nullopt);
  rig.frame(moved);
  for (int f = 0; f < 2; ++f)
    for (const auto& x : rig.frame(f ? rest : moved)) ADD_FAILURE() << "alarm after the fault ended: " << x.describe();
}

const Case kCases[] = {{FaultKind::DropDraw, SafetyKind::Telltale},    {FaultKind::WrongColour, SafetyKind::Telltale},
                       {FaultKind::CoverDraw, SafetyKind::Telltale},   {FaultKind::CoverText, SafetyKind::Telltale},
                       {FaultKind::StuckFrame, SafetyKind::Telltale},  {FaultKind::StaleNeedle, SafetyKind::Needle},
                       {FaultKind::DropDraw, SafetyKind::Needle}};

INSTANTIATE_TEST_SUITE_P(Both, Detection,
                         ::testing::Combine(::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                                            ::testing::ValuesIn(kCases)),
                         [](const auto& info) {
                           return param_name(info) + (std::get<1>(info.param).target == SafetyKind::Needle &&
                                                              std::get<1>(info.param).kind == FaultKind::DropDraw
                                                          ? "_needle"
                                                          : "");
                         });

class Frozen : public ::testing::TestWithParam<BackendKind> {};

// A stuck output while only a readout's text changes: no telltale or needle check can see it, the
// freeze check does (the text changed, the region's pixels did not).
TEST_P(Frozen, StuckOutputIsCaughtWhenOnlyAReadoutChanges) {
  MonitorRig rig(meter::testing::converted_cluster(), GetParam(), 4);
  auto state = rig.at(0.0);
  MonitorRig::set(state, "Vehicle.TraveledDistance", 1200.0);
  for (int f = 0; f < 3; ++f)
    for (const auto& x : rig.frame(state)) ADD_FAILURE() << "false alarm at clean frame " << f << ": " << x.describe();
  rig.renderer->inject(FaultInjection{FaultKind::StuckFrame, -1, {}});
  std::optional<int> caught;
  for (int k = 1; k <= 4 && !caught; ++k) {
    MonitorRig::set(state, "Vehicle.TraveledDistance", 1200.0 + k);
    for (const auto& x : rig.frame(state)) {
      EXPECT_EQ(x.region, "Text_Odometer") << x.describe();
      EXPECT_TRUE(x.frozen) << x.describe();
      caught = k;
      std::printf("LATENCY %s stuck-readout %d frame(s): %s\n", meter::platform::to_string(GetParam()).data(), k,
                  x.describe().c_str());
    }
  }
  ASSERT_TRUE(caught.has_value()) << "the frozen odometer was never caught";
  EXPECT_LE(*caught, kMaxLatency);
}

class SafePath : public ::testing::TestWithParam<BackendKind> {};

// A lit telltale whose draw was dropped is filled with its lit look's colour once caught: the
// frame presented after the check shows the lamp lit.
TEST_P(SafePath, ADroppedLitTelltaleIsRedrawnAsASolidFillOfItsLitColour) {
  MonitorRig rig(meter::testing::converted_cluster(), GetParam(), 4);
  const auto* region = meter::testing::first_region(rig.scene.integrity, SafetyKind::Telltale);
  ASSERT_NE(region, nullptr);
  rig.frame(rig.at(0.0));
  rig.renderer->inject(FaultInjection{FaultKind::DropDraw, rig.scene.find_node(region->node), {}});
  ASSERT_FALSE(rig.frame(rig.at(1.0)).empty()) << "the dropped lamp was not caught";
  EXPECT_EQ(rig.monitor->safe_redraws(), 1u);
  const meter::platform::Image& shown = rig.renderer->read();
  const meter::engine::RgbaView view{shown.rgba.data(), shown.width, shown.height, 0, 0, 0};
  const auto verdict = meter::engine::check_telltale(*region, view, true);
  EXPECT_TRUE(verdict.ok) << "after the safe path: " << verdict.seen;
}

INSTANTIATE_TEST_SUITE_P(Both, Frozen, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         [](const auto& info) { return std::string(meter::platform::to_string(info.param)); });
INSTANTIATE_TEST_SUITE_P(Both, SafePath, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         [](const auto& info) { return std::string(meter::platform::to_string(info.param)); });

}  // namespace
