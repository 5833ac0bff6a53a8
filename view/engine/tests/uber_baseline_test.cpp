// The uber-shader baseline (RendererOptions::uber_shader) is what bench/view times against the
// generated programs. A baseline that drew something else (wrong switches, lights not set, a
// texture unbound) would make that comparison meaningless, so it must draw the same cluster.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "meter/shadergen/shadergen.hpp"
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

platform::Image render(platform::GpuBackend& backend, const Scene& scene, bool uber, double speed) {
  RendererOptions o;
  static const shadergen::Program kUber = shadergen::generate_uber();
  o.width = 640, o.height = 240, o.uber_shader = uber ? &kUber : nullptr;
  Renderer r(backend, scene, o);
  BindingEvaluator ev(scene);
  protocol::SignalTable signals;
  signals.set(protocol::sig::kSpeed, {speed, protocol::SignalStatus::Valid, ""});
  ev.update(signals, true, -1.0);
  r.apply(ev.outputs());
  r.render(true, true);
  return r.last_image();
}

}  // namespace

TEST(UberBaseline, DrawsTheSameClusterAsTheGeneratedPrograms) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  const platform::Image generated = render(*backend, test::cluster_scene(), false, 87.0);
  const platform::Image uber = render(*backend, test::cluster_scene(), true, 87.0);
  const double db = platform::psnr(generated, uber);
  std::printf("[ uber     ] cluster uber vs generated: %.1f dB\n", db);
  if (db < 60.0) {
    const std::string out = test::scratch_dir("uber_baseline");
    platform::write_png(generated, fs::path(out) / "generated.png");
    platform::write_png(uber, fs::path(out) / "uber.png");
  }
  // Measured 79.4 dB: the cluster uses none of what the uber-shader lacks (environment map, morph,
  // Flat/Gouraud), so only the order of float operations differs (a few 1-level pixels). 60 dB
  // leaves room for that across drivers; one light mapped to the wrong slot measured 24.4 dB.
  EXPECT_GE(db, 60.0);
  // And the needle moves the same way: a different speed must change the uber image too.
  EXPECT_LT(platform::psnr(uber, render(*backend, test::cluster_scene(), true, 200.0)), 40.0);
}
