// The integrity bounds hold on correct frames: the committed scenes converted with their safety
// regions measured on EGL at MSAA 4 (as meter-convert does), then rendered by the engine on both
// backends at every MSAA count and at the quality-ladder points that keep the scene's geometry
// and shading, at nine states from every needle at its start to every needle at its end (lamps
// off below half, lit from half up). Every region's check must pass: zero false alarms. The
// largest difference per kind is printed; docs/integrity.md quotes these lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "bound_signals.hpp"
#include "process.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/integrity.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/engine/integrity_check.hpp"
#include "meter/engine/renderer.hpp"

namespace fs = std::filesystem;
using namespace meter;
using meter::bridge::Scene;

namespace {

struct SceneFiles {
  std::string name;
  fs::path glb, config;
};

const SceneFiles kScenes[] = {
    {"cluster", fs::path(METER_SOURCE_DIR) / "scenes/cluster/cluster.glb", fs::path(METER_SOURCE_DIR) / "scenes/cluster/cluster.scene.json"},
    {"minimal-gauge", fs::path(METER_SOURCE_DIR) / "scenes/minimal-gauge/minimal-gauge.glb",
     fs::path(METER_SOURCE_DIR) / "scenes/minimal-gauge/minimal-gauge.scene.json"},
};

// Ladder points: every MSAA count, and the texture filter, precision and interpolation points
// (which leave the geometry and the shading model alone; see docs/integrity.md for shading and LOD).
const char* kLadder[] = {"msaa=1", "msaa=2", "msaa=4", "msaa=8", "filter=nearest", "precision=mediump", "interpolation=affine"};
const double kFractions[] = {0.0, 0.13, 0.27, 0.41, 0.5, 0.66, 0.79, 0.93, 1.0};

engine::RgbaView view_of(const platform::Image& img) { return {img.rgba.data(), img.width, img.height, 0, 0, 0}; }

class IntegrityBounds : public ::testing::TestWithParam<std::string> {};

TEST_P(IntegrityBounds, CorrectFramesPassEveryCheck) {
  const std::string backend_name = GetParam();
  for (const auto& files : kScenes) {
    convert::ConvertOptions co;
    co.optimize = false;  // the ladder regenerates programs; compare points on an unfolded scene
    Scene scene = convert::convert_gltf(files.glb.string(), meter::config::load_scene_config(files.config.string()), co).scene;
    // One GL context at a time: the EGL one measures and renders the readouts' references (the
    // same states on EGL at each MSAA count, as meter-verify re-renders with the run's --msaa),
    // then goes before the tested one.
    convert::IntegrityMeasurement measured;
    std::map<int, std::vector<platform::Image>> references;  // by MSAA count
    {
      auto egl = platform::create_backend(platform::BackendKind::Egl);
      measured = convert::measure_integrity(scene, *egl);
      scene.integrity = measured.table;
      for (int msaa : {1, 2, 4, 8}) {
        engine::RendererOptions ro;
        ro.msaa = msaa;
        engine::Renderer reference(*egl, scene, ro);
        engine::BindingEvaluator ev(scene);
        for (double f : kFractions) {
          ev.update(meter::testing::bound_signals_at(scene.config, f), true, -1.0);
          reference.apply(ev.outputs());
          reference.render(false, true);
          references[msaa].push_back(reference.last_image());
        }
      }
    }
    ASSERT_FALSE(scene.integrity.empty()) << files.name;
    // Every safety binding has its region: one telltale per signal of the visibility / emissive /
    // colour bindings, one needle per animation binding (each rotates one node in these scenes),
    // one readout per text binding; nothing left out.
    std::set<std::string> telltale_signals;
    std::size_t needles = 0, readouts = 0;
    for (const auto& b : scene.config.bindings) {
      if ((b.kind == bridge::BindingKind::Visibility || b.kind == bridge::BindingKind::Emissive ||
           b.kind == bridge::BindingKind::Color) && b.safety) {
        telltale_signals.insert(b.signal);
      }
      needles += b.kind == bridge::BindingKind::Animation;
      readouts += b.kind == bridge::BindingKind::Text;
    }
    std::map<bridge::SafetyKind, std::size_t> kinds;
    for (const auto& r : scene.integrity.regions) ++kinds[r.kind];
    EXPECT_EQ(kinds[bridge::SafetyKind::Telltale], telltale_signals.size()) << files.name;
    // A binding the converter could not measure is in `skipped` instead (allowed below by name).
    auto unmeasured = [&](const char* kind) {
      std::size_t n = 0;
      for (const auto& s : measured.skipped) n += s.find(std::string("(") + kind + " ") != std::string::npos;
      return n;
    };
    EXPECT_EQ(kinds[bridge::SafetyKind::Needle] + unmeasured("needle"), needles) << files.name;
    EXPECT_EQ(kinds[bridge::SafetyKind::Readout] + unmeasured("readout"), readouts) << files.name;
    // Regions the converter could not measure, each with its reason. The cluster's trip-computer
    // page (page 2) is hidden in the state the converter renders, so its two texts put no ink on
    // the frame. Every needle is measured, the tachometer's too: its red zone and grey print share
    // no colour with the needle's core. Anything else left unmeasured fails here by name.
    std::set<std::string> allowed_unmeasured;
    if (files.name == "cluster") allowed_unmeasured = {"Text_TripPage", "Text_TripFuel"};
    for (const auto& s : measured.skipped) {
      const std::string region = s.substr(0, s.find(' '));
      EXPECT_TRUE(allowed_unmeasured.count(region)) << files.name << ": " << s;
    }
    std::printf("%s: %zu regions, %zu not monitored, needle interpolation %.3f deg\n", files.name.c_str(),
                scene.integrity.regions.size(), measured.skipped.size(), measured.needle_interpolation_deg);
    for (const auto& s : measured.skipped) std::printf("  not monitored: %s\n", s.c_str());
    auto backend = platform::create_backend(*platform::parse_backend_kind(backend_name));
    for (const char* point : kLadder) {
      Scene variant = scene;
      const auto q = convert::parse_quality(point);
      convert::apply_quality(variant, q);
      engine::RendererOptions ro;
      ro.msaa = q.msaa.value_or(4);
      engine::Renderer renderer(*backend, variant, ro);
      engine::BindingEvaluator ev(variant);
      std::map<bridge::SafetyKind, double> worst;
      int checks = 0;
      for (std::size_t k = 0; k < std::size(kFractions); ++k) {
        const double f = kFractions[k];
        ev.update(meter::testing::bound_signals_at(variant.config, f), true, -1.0);
        renderer.apply(ev.outputs());
        renderer.render(false, true);
        const auto expected = engine::expected_states(variant.integrity, variant, ev);
        for (std::size_t i = 0; i < variant.integrity.regions.size(); ++i) {
          const auto& region = variant.integrity.regions[i];
          if (!expected[i].known) continue;
          const auto ref = view_of(references[ro.msaa][k]);
          const auto v = engine::check_region(region, view_of(renderer.last_image()), expected[i], &ref);
          ++checks;
          worst[region.kind] = std::max(worst[region.kind], v.difference);
          EXPECT_TRUE(v.ok) << files.name << " " << backend_name << " " << point << " at " << f << ": " << region.name
                            << " expected " << v.expected << ", seen " << v.seen << " (difference " << v.difference << ")";
        }
      }
      std::printf("%-13s %-6s %-20s %4d checks; largest difference: telltale %.2f, needle %.3f deg, readout %.0f px\n",
                  files.name.c_str(), backend_name.c_str(), point, checks, worst[bridge::SafetyKind::Telltale],
                  worst[bridge::SafetyKind::Needle], worst[bridge::SafetyKind::Readout]);
    }
  }
}

// meter-convert --report lists the table it stored.
TEST(IntegrityReport, MeterConvertListsTheRegions) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "tests" / "integrity" / "report";
  fs::remove_all(dir);
  fs::create_directories(dir);
  meter::testing::ChildProcess p({meter::testing::built_executable("meter-convert"), kScenes[1].glb.string(), "--config",
                                  kScenes[1].config.string(), "-o", (dir / "gauge.msp").string(), "--report"},
                                 (dir / "convert.log").string());
  const auto rc = p.wait_for(std::chrono::seconds(120));
  ASSERT_TRUE(rc.has_value()) << p.log();
  ASSERT_EQ(*rc, 0) << p.log();
  EXPECT_NE(p.log().find("integrity: 1 safety regions at 640x480"), std::string::npos) << p.log();
  EXPECT_NE(p.log().find("  needle   Needle                 Vehicle.Speed"), std::string::npos) << p.log();
  // The summary line: "... 1 safety regions, <levels>, 0 repairs)".
  EXPECT_NE(p.log().find(" 1 safety regions, "), std::string::npos) << p.log();
  EXPECT_NE(p.log().find(", 0 repairs)"), std::string::npos) << p.log();
  const auto table = engine::read_package((dir / "gauge.msp").string()).integrity;
  ASSERT_EQ(table.regions.size(), 1u);
  EXPECT_EQ(table.regions[0].needle.samples.size(), 25u);
}

INSTANTIATE_TEST_SUITE_P(Backends, IntegrityBounds, ::testing::Values("egl", "osmesa"),
                         [](const auto& info) { return info.param; });

}  // namespace
