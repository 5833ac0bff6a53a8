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
  // Rest: every needle at its range's start (or a fifth of it on odd frames), every telltale dark
  // (booleans: a lamp's emissive is only ever off or on). Then the state every item must
  // show differently (needles at full scale, telltales lit) arrives in the frame the fault starts.
  const auto rest = rig.at(0.0), moved = rig.at(1.0);
  for (int f = 0; f < kCleanFrames; ++f) {
    const auto faults = rig.frame(f % 2 ? rig.at(0.2) : rest);
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

}  // namespace
