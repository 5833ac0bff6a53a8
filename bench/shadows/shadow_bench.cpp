// shadow_bench: the shadow feature scene (a teapot on a floor under a sun and a spot that both cast,
// 640x480, MSAA 4) on EGL, drawn four ways in one run, interleaved, every frame in full: without
// and with shadows, the teapot still (each map drawn once, then only looked up) and the teapot
// moving every frame (both maps drawn again each frame). Prints the median frame times and the two
// ratios: what the lookups cost, and what lookups plus a depth pass per light cost.
// Usage: shadow_bench [frames]   (default 100)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <vector>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "bench_stats.hpp"

using meter::bench::median;

namespace fs = std::filesystem;
using namespace meter;
using Clock = std::chrono::steady_clock;

namespace {

// The teapot lifted by 5 cm at t = 1 s: a caster that moves, as a needle does on a cluster.
engine::Scene with_moving_teapot(engine::Scene s) {
  const int pot = s.find_node("Teapot");
  if (pot < 0) throw std::runtime_error("shadow_bench: no node \"Teapot\"");
  const glm::vec3 t = s.nodes[std::size_t(pot)].translation;
  engine::Animation a;
  a.name = "Lift";
  a.samplers.push_back({engine::Interpolation::Linear, 3, {0.0f, 1.0f}, {t.x, t.y, t.z, t.x, t.y + 0.05f, t.z}});
  a.channels.push_back({0, pot, engine::TargetPath::Translation});
  a.end = 1.0f;
  s.animations.push_back(a);
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(10, std::atoi(argv[1])) : 100;
  const fs::path dir = fs::path(METER_SOURCE_DIR) / "scenes/features/shadow";
  const engine::SceneConfig cfg = meter::config::load_scene_config((dir / "scene.json").string());
  const engine::Scene on = convert::convert_gltf((dir / "shadow.glb").string(), cfg, {}).scene;
  engine::Scene off = on;
  convert::apply_quality(off, convert::parse_quality("shadows=off"));
  const std::vector<std::pair<const char*, engine::Scene>> variants = {
      {"no shadows, teapot still", off}, {"shadows, teapot still", on},
      {"no shadows, teapot moving", with_moving_teapot(off)}, {"shadows, teapot moving", with_moving_teapot(on)}};
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  std::vector<std::unique_ptr<engine::Renderer>> renderers;
  for (const auto& [name, scene] : variants) {
    renderers.push_back(std::make_unique<engine::Renderer>(*backend, scene, engine::RendererOptions{}));
    renderers.back()->render(true);  // programs compiled, maps drawn
  }
  std::vector<std::vector<double>> ms(variants.size());
  for (int f = 0; f < frames; ++f)
    for (std::size_t v = 0; v < variants.size(); ++v) {
      engine::Renderer& r = *renderers[v];
      if (!variants[v].second.animations.empty()) {
        engine::BindingOutputs out = engine::resting_outputs(variants[v].second);
        out.animation_time.assign(out.animation_time.size(), double(f % 2));
        r.apply(out);
      }
      const auto t0 = Clock::now();
      r.render(true);
      backend->gl().Finish();
      ms[v].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
  std::printf("shadow scene, 640x480 MSAA 4, %s, %d frames each, interleaved\n", backend->renderer_info().c_str(), frames);
  for (std::size_t v = 0; v < variants.size(); ++v)
    std::printf("%-28s %8.3f ms  (shadow maps drawn %llu times)\n", variants[v].first, median(ms[v]),
                static_cast<unsigned long long>(renderers[v]->stats().shadow_map_draws));
  std::printf("%-28s %8.2f x\n", "lookups (still)", median(ms[1]) / median(ms[0]));
  std::printf("%-28s %8.2f x\n", "lookups + maps (moving)", median(ms[3]) / median(ms[2]));
  return 0;
}
