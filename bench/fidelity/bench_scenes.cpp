// Scenes, states, renders and the machine line of meter-bench.
#include "bench_scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/utsname.h>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/platform/render_target.hpp"
#include "reference_state.hpp"

namespace meter::bench {

std::vector<SceneSpec> all_scenes() {
  const std::vector<std::tuple<const char*, const char*, double>> features = {
      {"ambient", "Ambient", 38.68},   {"diffuse", "Diffuse", 37.13},     {"specular", "Specular", 45.64},
      {"shininess", "Shininess", 43.10}, {"emission", "Emission", 34.68},   {"bump", "Bump", 33.91},
      {"reflection", "Reflection", 31.28}, {"envmap2d", "Environment map (2D)", 38.54},
      {"skinning", "Skinning", 33.97}, {"morphing", "Morphing", 34.35},   {"spot", "Spot light", 38.11},
      {"omni", "Omni light", 39.02},   {"shadow", "", -1.0}};
  std::vector<SceneSpec> s;
  for (const auto& [n, paper, db] : features) {
    const fs::path d = kRoot / "scenes/features" / n;
    s.push_back({n, (d / (std::string(n) + ".glb")).string(), (d / "scene.json").string(), (d / "reference.png").string(), db, paper});
  }
  const fs::path c = kRoot / "scenes/cluster";
  s.push_back({"cluster", (c / "cluster.glb").string(), (c / "cluster.scene.json").string(),
               (c / "preview-blender.png").string(), -1.0, ""});
  return s;
}

engine::BindingOutputs reference_state(const engine::Scene& scene, bool cluster) {
  return cluster ? testing::cluster_reference_state(scene) : testing::feature_reference_state(scene);
}

engine::Scene convert(const SceneSpec& s, bool optimize) {
  // As shipped, concatenation groups included: fidelity is the product's (merged draws differ from
  // unmerged ones in at most 1e-4 of the pixels, view/engine/tests/concat_render_test.cpp).
  const engine::SceneConfig cfg = meter::config::load_scene_config(s.config);
  convert::ConvertOptions o;
  o.optimize = optimize;
  return convert::convert_gltf(s.glb, cfg, o).scene;
}

platform::Image render_once(platform::GpuBackend& backend, const engine::Scene& scene, const engine::BindingOutputs& state,
                            engine::RendererOptions o) {
  engine::Renderer r(backend, scene, o);
  r.apply(state);
  r.render(true, true);
  return r.last_image();
}

std::string machine_line(const platform::GpuBackend& backend) {
  utsname u{};
  uname(&u);
  std::string cpu = "?";
  std::ifstream ci("/proc/cpuinfo");
  for (std::string line; std::getline(ci, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return std::string(date) + "; " + cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores (shared), " +
         u.sysname + " " + u.release + "; " + backend.renderer_info();
}

std::string fmt(double v, int prec) {
  if (std::isnan(v)) return "—";
  if (std::isinf(v)) return "identical";
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = p * double(v.size() - 1);
  const auto lo = std::size_t(std::floor(pos));
  const auto hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (pos - double(lo)) * (v[hi] - v[lo]);
}

std::size_t count_non_background(const platform::Image& img) {
  const auto* bg = img.pixel(0, 0);
  return platform::object_mask(img, {bg[0], bg[1], bg[2]}, 0).count();
}

}  // namespace meter::bench
