// Mesh concatenation render equivalence: the cluster converted with
// scenes/cluster/cluster.scene.json (17 groups, 142 of 163 objects) is drawn merged and
// unmerged from ONE package on both backends in several states, and the images are compared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

// Tolerance. Merged vertices are transformed by the CPU (glm, float) and unmerged ones by the
// vertex shader (llvmpipe, float, possibly FMA-contracted): positions agree to ~1 ulp, so a sample
// lying exactly on a triangle edge may flip coverage. With MSAA 4 that changes an edge pixel by
// 1/4 of the edge contrast at most (<= 64 levels), on a handful of pixels. Measured: 2-3 of the
// 153,600 pixels differ, by at most 8 levels, in every state on both backends. The bound allows
// 0.01 % (15 pixels) up to 64 levels, while a missing tick or numeral (tens of pixels at ~200
// levels) or a telltale window drawn in the wrong state (hundreds of pixels) fails it.
constexpr double kMaxDifferingFraction = 1e-4;
constexpr int kMaxLevelDifference = 64;

const Scene& cluster() { return test::cluster_scene(); }

struct Diff {
  std::size_t differing = 0;
  int max_level = 0;
};

Diff diff(const platform::Image& a, const platform::Image& b) {
  Diff d;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  for (std::size_t p = 0; p + 3 < a.rgba.size() && p + 3 < b.rgba.size(); p += 4) {
    int m = 0;
    for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(int(a.rgba[p + std::size_t(c)]) - int(b.rgba[p + std::size_t(c)])));
    if (m) ++d.differing, d.max_level = std::max(d.max_level, m);
  }
  return d;
}

protocol::SignalId sig(std::string_view name) {
  const auto* s = protocol::find_signal(name);
  if (!s) throw std::runtime_error("no catalog signal " + std::string(name));
  return s->id;
}

struct State {
  std::string name;
  std::vector<std::pair<std::string, double>> values;
  std::vector<std::string> hidden;  // grouped members hidden directly (visibility outputs)
};

class ConcatRender : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override {
    backend_ = platform::create_backend(GetParam());
    RendererOptions merged, plain;
    merged.width = plain.width = 640, merged.height = plain.height = 240;  // half size: fast, same geometry
    plain.concatenate = false;
    merged_ = std::make_unique<Renderer>(*backend_, cluster(), merged);
    plain_ = std::make_unique<Renderer>(*backend_, cluster(), plain);
    evaluator_ = std::make_unique<BindingEvaluator>(cluster());
  }
  BindingOutputs outputs(const State& st) {
    protocol::SignalTable v;
    for (const auto& [n, x] : st.values) v.set(sig(n), {x, protocol::SignalStatus::Valid, ""});
    evaluator_->update(v, true, -1.0);
    BindingOutputs o = evaluator_->outputs();
    o.node_visible.resize(cluster().nodes.size(), -1);
    for (const auto& h : st.hidden) {
      const int n = cluster().find_node(h);
      EXPECT_GE(n, 0) << h;
      if (n >= 0) o.node_visible[static_cast<std::size_t>(n)] = 0;
    }
    return o;
  }
  void check(const State& st) {
    const BindingOutputs o = outputs(st);
    merged_->apply(o);
    plain_->apply(o);
    merged_->render(true, true);
    plain_->render(true, true);
    const Diff d = diff(merged_->last_image(), plain_->last_image());
    const double total = double(merged_->width()) * merged_->height();
    // Printed so the measured difference (docs/concatenation.md) can be re-read from any run.
    std::printf("[ concat   ] %-20s %-7s %6zu pixels differ (%.4f %%), max %d levels\n", st.name.c_str(),
                std::string(platform::to_string(GetParam())).c_str(), d.differing, 100.0 * double(d.differing) / total, d.max_level);
    if (d.differing) {
      const std::string out = test::scratch_dir("concat_" + st.name + "_" + std::string(platform::to_string(GetParam())));
      platform::write_png(merged_->last_image(), fs::path(out) / "merged.png");
      platform::write_png(plain_->last_image(), fs::path(out) / "unmerged.png");
    }
    EXPECT_LE(double(d.differing) / total, kMaxDifferingFraction) << st.name << ": " << d.differing << " pixels differ";
    EXPECT_LE(d.max_level, kMaxLevelDifference) << st.name;
  }
  std::unique_ptr<platform::GpuBackend> backend_;
  std::unique_ptr<Renderer> merged_, plain_;
  std::unique_ptr<BindingEvaluator> evaluator_;
};

}  // namespace

TEST(ConcatCluster, GroupedConfigMergesAndDrawsFewerCalls) {
  const Scene& s = cluster();
  ASSERT_EQ(s.groups.size(), 17u);
  std::size_t members = 0;
  for (const auto& g : s.groups) members += g.draws.size();
  EXPECT_EQ(members, 142u);
}

TEST_P(ConcatRender, MergedEqualsUnmergedInEveryState) {
  const std::vector<State> states = {
      {"rest_failsafe", {}, {}},
      {"driving", {{"Vehicle.Speed", 87}, {"Vehicle.Powertrain.CombustionEngine.Speed", 2400},
                   {"Vehicle.Powertrain.FuelSystem.RelativeLevel", 62}, {"Vehicle.Powertrain.CombustionEngine.ECT", 90}}, {}},
      {"all_telltales_on", {{"Vehicle.Speed", 20}, {"Cluster.Telltale.TurnLeft", 1}, {"Cluster.Telltale.LowBeam", 1},
                            {"Cluster.Telltale.HighBeam", 1}, {"Cluster.Telltale.ABS", 1}, {"Cluster.Telltale.Battery", 1},
                            {"Cluster.Telltale.CheckEngine", 1}, {"Cluster.Telltale.FuelLow", 1}}, {}},
      // Grouped members hidden: the first member (the representative), one in the middle, the last.
      {"members_hidden", {{"Vehicle.Speed", 180}, {"Cluster.Telltale.ABS", 1}},
       {"Speedo_Arc", "Speedo_Num_00100", "Speedo_Num_00260", "TTWindow_TurnLeft", "TTWindow_ABS", "Tacho_Tick_03000"}},
      // ... and shown again (the index array must grow back).
      {"members_shown_again", {{"Vehicle.Speed", 180}, {"Cluster.Telltale.ABS", 0}}, {}},
      {"whole_group_hidden", {{"Vehicle.Speed", 5}}, {"Speedo_Needle", "Tacho_Needle"}},
      {"redline", {{"Vehicle.Speed", 260}, {"Vehicle.Powertrain.CombustionEngine.Speed", 8000},
                   {"Vehicle.Powertrain.FuelSystem.RelativeLevel", 100}, {"Vehicle.Powertrain.CombustionEngine.ECT", 130}}, {}},
  };
  for (const auto& st : states) check(st);
  EXPECT_LT(merged_->stats().draw_calls, plain_->stats().draw_calls);
}

TEST_P(ConcatRender, StaticMembersAreNeverRetransformed) {
  State st{"a", {{"Vehicle.Speed", 50}}, {}};
  merged_->apply(outputs(st));
  merged_->render(true, false);
  const auto after_first = merged_->stats();
  // Every member was written once at the first frame.
  std::size_t members = 0;
  for (const auto& g : cluster().groups) members += g.draws.size();
  EXPECT_EQ(after_first.member_transforms, members);
  // Speed changes: only the speedo needle moves; it is one member of "main_needles".
  st.values = {{"Vehicle.Speed", 120}};
  merged_->apply(outputs(st));
  merged_->render(true, false);
  EXPECT_EQ(merged_->stats().member_transforms, after_first.member_transforms + 1);
  // Same state again: nothing to redo.
  merged_->apply(outputs(st));
  merged_->render(true, false);
  EXPECT_EQ(merged_->stats().member_transforms, after_first.member_transforms + 1);
  EXPECT_EQ(merged_->stats().index_rebuilds, after_first.index_rebuilds);
  // Hiding a member rebuilds its group's indices and rewrites no positions.
  st.hidden = {"Speedo_Num_00100"};
  merged_->apply(outputs(st));
  merged_->render(true, false);
  EXPECT_EQ(merged_->stats().member_transforms, after_first.member_transforms + 1);
  EXPECT_EQ(merged_->stats().index_rebuilds, after_first.index_rebuilds + 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, ConcatRender, ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
