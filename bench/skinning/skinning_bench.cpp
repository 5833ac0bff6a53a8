// skinning_bench: the skinning feature scene (a teapot bent by a two-bone armature, 640x480, MSAA 4)
// on EGL: the median time of one recomputation of its skinned normals (skin_normals: deform, face
// normals, carry back; the CPU side of a pose change) beside the median time of a full frame of the
// same scene, and their ratio, measured in one run, interleaved.
// Usage: skinning_bench [runs]   (default 200)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/evaluation/skinned_normals.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "bench_stats.hpp"

using meter::bench::median;
using meter::bench::ms_since;

namespace fs = std::filesystem;
using namespace meter;
using Clock = std::chrono::steady_clock;


int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  const fs::path dir = fs::path(METER_SOURCE_DIR) / "scenes/features/skinning";
  const engine::SceneConfig cfg = meter::config::load_scene_config((dir / "scene.json").string());
  const engine::Scene scene = convert::convert_gltf((dir / "skinning.glb").string(), cfg, {}).scene;
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  engine::Renderer renderer(*backend, scene, engine::RendererOptions{});
  renderer.render(true);  // programs compiled, buffers touched

  // The skinned draw and its joint matrices at the scene's time, as the renderer computes them.
  const engine::DrawItem* skinned = nullptr;
  for (const auto& d : scene.draws)
    if (scene.nodes[std::size_t(d.node)].skin >= 0) skinned = &d;
  if (!skinned) {
    std::fprintf(stderr, "skinning_bench: no skinned draw in %s\n", dir.c_str());
    return 1;
  }
  const engine::Primitive& prim = scene.meshes[std::size_t(skinned->mesh)].primitives[std::size_t(skinned->primitive)];
  const engine::SkinnedNormalsLayout layout = engine::skinned_normals_layout(prim);
  engine::SceneEvaluator evaluator(scene);
  evaluator.update_world();
  const std::vector<glm::mat4>& world = evaluator.world();
  const auto node = std::size_t(skinned->node);
  const auto joints = engine::joint_matrices(scene.skins[std::size_t(scene.nodes[node].skin)], world, world[node]);
  std::vector<float> vertices = prim.vertices;

  std::vector<double> normals_ms, frame_ms;
  for (int i = 0; i < runs; ++i) {
    auto t0 = Clock::now();
    (void)engine::skin_normals(prim, layout, joints, vertices);
    normals_ms.push_back(ms_since(t0));
    t0 = Clock::now();
    renderer.render(true);
    backend->gl().Finish();
    frame_ms.push_back(ms_since(t0));
  }
  const double n = median(normals_ms), f = median(frame_ms);
  std::printf("skinning scene, %u vertices, %zu triangles, %s\n", prim.vertex_count, prim.indices.size() / 3,
              backend->renderer_info().c_str());
  std::printf("%-40s %9.4f ms (median of %d)\n", "skinned normals recomputed (CPU)", n, runs);
  std::printf("%-40s %9.4f ms (median of %d)\n", "full frame 640x480 MSAA 4 (render+finish)", f, runs);
  std::printf("%-40s %9.2f %%\n", "normals / frame", 100.0 * n / f);
  return 0;
}
