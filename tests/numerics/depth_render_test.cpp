// Depth: coplanar-looking dial layers (face, tick decals 1 mm above it, needle 2 mm above it)
// never z-fight, rendered through the engine at camera distances 0.5 .. 30 m on both backends
// (docs/numerics.md, "Depth"). The scene is built here; the camera's znear/zfar are 0.1 / 100 m
// and the engine's depth buffer is DEPTH_COMPONENT24 with a standard [-1, 1] GL projection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gltf_builder.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
using meter::numerics::GltfBuilder;

namespace {

constexpr double kNear = 0.1, kFar = 100.0;
constexpr float kGap = 0.001f;  // 1 mm between layers, as in scenes/cluster (z = 0.004 / 0.005 / 0.006)
constexpr int kSize = 128;

// Smallest eye-space depth step a 24-bit depth buffer resolves at distance z (window depth
// d(z) = (f/(f-n)) (1 - n/z) for glm's [-1,1] clip mapped to [0,1]; dd/dz = f n / ((f-n) z^2)).
double depth24_step(double z) { return std::ldexp(1.0, -24) * (kFar - kNear) * z * z / (kFar * kNear); }

std::string write_scene(double distance, const std::string& dir) {
  GltfBuilder b;
  const int face = b.material("Face", {0.05, 0.05, 0.05, 1}, true);
  const int tick = b.material("Tick", {1, 0, 0, 1}, true);
  const int needle = b.material("Needle", {0, 1, 0, 1}, true);
  b.node({{"name", "Face"}, {"mesh", b.quad("Face", -1, -1, 1, 1, 0.0f, face)}});
  // Four tick decals centred at (+-0.5, +-0.5), 0.3 x 0.3, one gap above the face.
  const int tick_mesh = b.quad("Tick", -0.15f, -0.15f, 0.15f, 0.15f, 0.0f, tick);
  for (int i = 0; i < 4; ++i) {
    b.node({{"name", "Tick" + std::to_string(i)}, {"mesh", tick_mesh},
            {"translation", {i % 2 ? 0.5 : -0.5, i / 2 ? 0.5 : -0.5, double(kGap)}}});
  }
  // Needle: a bar along y over the two ticks on the right half, two gaps above the face.
  b.node({{"name", "Needle"}, {"mesh", b.quad("Needle", -0.05f, -0.8f, 0.05f, 0.8f, 0.0f, needle)}, {"translation", {0.5, 0.0, 2.0 * kGap}}});
  // Camera on +z looking down -z; yfov keeps the 2.4 m window framed at every distance.
  const double yfov = 2.0 * std::atan(1.2 / distance);
  b.node({{"name", "Cam"}, {"camera", b.camera(yfov, kNear, kFar, 1.0)}, {"translation", {0.0, 0.0, distance}}});
  return b.write(std::filesystem::path(dir) / "layers.gltf");
}

class DepthTest : public ::testing::TestWithParam<platform::BackendKind> {};

}  // namespace

TEST_P(DepthTest, DialLayersNeverZFightAtAnyCameraDistance) {
  auto backend = platform::create_backend(GetParam());
  const std::string cfg = R"({"format": "meter-scene-config/1", "size": [128, 128], "camera": "Cam", "clear_color": [0, 0, 1, 1]})";
  for (double d : {0.5, 1.0, 3.0, 10.0, 30.0}) {
    SCOPED_TRACE("camera distance " + std::to_string(d) + " m");
    // Precondition of the design: the layer gap is at least 1.5 depth steps at this distance
    // (at 30 m one 24-bit step is 0.54 mm). The render below is the proof.
    ASSERT_GE(kGap, 1.5 * depth24_step(d));
    const auto dir = numerics::scratch("depth-" + std::string(platform::to_string(GetParam())) + "-" + std::to_string(int(d * 10)));
    const Scene scene = convert_gltf(write_scene(d, dir.string()), meter::config::parse_scene_config(cfg), ConvertOptions{false}).scene;
    RendererOptions o;
    o.msaa = 1;  // exact per-pixel depth results; no resolve blending
    Renderer r(*backend, scene, o);
    BindingEvaluator eval(scene);
    eval.update(protocol::SignalTable{}, true, -1.0);  // nothing known: every binding NotAvailable (its failsafe where it has one)
    r.apply(eval.outputs());
    r.render(true, true);
    const platform::Image& img = r.last_image();
    ASSERT_EQ(img.width, kSize);
    // Count every pixel of each layer's interior (1 px margin from the projected edges; msaa 1 samples pixel centres).
    auto px = [&](double x, double y) {  // world (x, y) on the dial -> pixel
      const double half = 1.2;
      return std::pair<int, int>{int(std::floor((x / half * 0.5 + 0.5) * kSize)), int(std::floor((0.5 - y / half * 0.5) * kSize))};
    };
    auto region = [&](double x0, double y0, double x1, double y1, auto pred) {
      auto [ax, ay] = px(x0, y1);
      auto [bx, by] = px(x1, y0);
      int bad = 0, n = 0;
      for (int y = ay + 1; y <= by - 1; ++y)
        for (int x = ax + 1; x <= bx - 1; ++x, ++n)
          if (!pred(img.pixel(x, y))) ++bad;
      EXPECT_GT(n, 20);
      return bad;
    };
    auto red = [](const std::uint8_t* p) { return p[0] == 255 && p[1] == 0 && p[2] == 0; };
    auto green = [](const std::uint8_t* p) { return p[0] == 0 && p[1] == 255 && p[2] == 0; };
    const std::uint8_t* face_px = img.pixel(kSize / 2 - 20, kSize / 2);  // face only
    const std::uint8_t fr = face_px[0];
    EXPECT_TRUE(face_px[0] == face_px[1] && face_px[1] == face_px[2] && fr > 0 && fr < 255);
    auto facec = [&](const std::uint8_t* p) { return p[0] == fr && p[1] == fr && p[2] == fr; };
    // Left ticks: all red. Right ticks: red except under the needle column.
    EXPECT_EQ(region(-0.65, 0.35, -0.35, 0.65, red), 0);
    EXPECT_EQ(region(-0.65, -0.65, -0.35, -0.35, red), 0);
    EXPECT_EQ(region(0.35, 0.35, 0.43, 0.65, red), 0);
    EXPECT_EQ(region(0.57, -0.65, 0.65, -0.35, red), 0);
    // Needle over ticks and over the face: all green.
    EXPECT_EQ(region(0.45, -0.78, 0.55, 0.78, green), 0);
    // Bare face between the ticks: the face colour exactly.
    EXPECT_EQ(region(-0.3, -0.3, 0.3, 0.3, facec), 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, DepthTest, ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
