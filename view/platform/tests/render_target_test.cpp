// Render targets on both backends: exact pixels, MSAA, sRGB encode, linear blending, depth,
// row order, and EGL == OSMesa for the same GLSL ES 3.00 draw.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <span>

#include "gl_test_util.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"

namespace mp = meter::platform;
using mp::BackendKind;

class RenderTargetTest : public ::testing::TestWithParam<BackendKind> {
 protected:
  void SetUp() override { backend_ = mp::create_backend(GetParam()); }
  const mp::Gl& gl() const { return backend_->gl(); }
  std::unique_ptr<mp::GpuBackend> backend_;
};

INSTANTIATE_TEST_SUITE_P(Both, RenderTargetTest, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

TEST_P(RenderTargetTest, ClearColourReadsBackExactly) {
  mp::RenderTarget target(*backend_, {.width = 33, .height = 17, .samples = 4, .srgb = false});
  EXPECT_EQ(target.samples(), 4);
  gl().ClearColor(0.2f, 0.4f, 0.6f, 1.0f);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  EXPECT_EQ(target.resolve_and_read(), mp::Image(33, 17, 51, 102, 153, 255));
}

TEST_P(RenderTargetTest, PixelAlignedRectangleIsExactWithAndWithoutMsaa) {
  for (int samples : {1, 4}) {
    SCOPED_TRACE("samples " + std::to_string(samples));
    mp::RenderTarget target(*backend_, {.width = 40, .height = 20, .samples = samples, .srgb = false});
    mp::test::ColorProgram program(gl());
    gl().ClearColor(0, 0, 0, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    program.rect_pixels(40, 20, 8, 3, 24, 12, 1.0f, 0.0f, 0.0f, 1.0f);
    const mp::Image img = target.resolve_and_read();
    mp::Image expected(40, 20, 0, 0, 0);
    for (int y = 3; y < 12; ++y)  // y counted from the top: checks the row flip too
      for (int x = 8; x < 24; ++x) expected.pixel(x, y)[0] = 255;
    EXPECT_EQ(img, expected);
  }
}

TEST_P(RenderTargetTest, MsaaSmoothsDiagonalEdges) {
  auto partial_pixels = [&](int samples) {
    mp::RenderTarget target(*backend_, {.width = 32, .height = 32, .samples = samples, .srgb = false});
    mp::test::ColorProgram program(gl());
    gl().ClearColor(0, 0, 0, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT);
    program.draw({-0.9f, -0.9f, 1, 1, 1, 1, 0.9f, -0.7f, 1, 1, 1, 1, -0.2f, 0.9f, 1, 1, 1, 1});
    const mp::Image img = target.resolve_and_read();
    int partial = 0, full = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const int v = img.pixel(x, y)[0];
        partial += v > 0 && v < 255;
        full += v == 255;
      }
    EXPECT_GT(full, 100);
    return partial;
  };
  EXPECT_EQ(partial_pixels(1), 0);
  EXPECT_GT(partial_pixels(4), 20);
}

TEST_P(RenderTargetTest, SrgbTargetEncodesLinearHalfTo188) {
  // sRGB of linear 0.5 is 0.73536 * 255 = 187.52 -> 188 with exact rounding.
  ASSERT_EQ(mp::linear_to_srgb8(0.5), 188);
  for (int samples : {1, 4}) {
    SCOPED_TRACE("samples " + std::to_string(samples));
    mp::RenderTarget target(*backend_, {.width = 16, .height = 16, .samples = samples});
    ASSERT_TRUE(target.srgb());
    gl().ClearColor(0.5f, 0.5f, 0.5f, 1.0f);
    gl().Clear(GL_COLOR_BUFFER_BIT);
    mp::test::ColorProgram program(gl());
    program.rect_pixels(16, 16, 0, 0, 8, 16, 0.5f, 0.0f, 1.0f, 1.0f);
    const mp::Image img = target.resolve_and_read();
    // glClear is a write too: GL encodes the clear colour exactly (and the MSAA resolve keeps it).
    EXPECT_EQ(img.pixel(12, 7)[0], 188);
    EXPECT_EQ(img.pixel(12, 7)[1], 188);
    // Shader output goes through llvmpipe's fast sRGB encoder, which is accurate to 0.63 of an
    // 8-bit step (GL allows approximate conversion; D3D10 specifies 0.6): 0.5 gives 187 there,
    // 0.52 of a step from the exact 187.52. Same encoder on both backends (see the sweep below).
    const std::uint8_t* drawn = img.pixel(3, 7);
    EXPECT_NEAR(drawn[0], 187.52, 0.65);
    EXPECT_EQ(drawn[1], 0);
    EXPECT_EQ(drawn[2], 255);
  }
}

TEST_P(RenderTargetTest, SrgbEncodeOfShaderOutputIsWithinTwoThirdsOfAStep) {
  // 1024 linear values, one per pixel column: each stored byte within 0.65 of exact sRGB * 255,
  // and the proportion of bytes that differ from exact rounding stays small.
  const int w = 1024;
  mp::RenderTarget target(*backend_, {.width = w, .height = 1, .samples = 1});
  mp::test::ColorProgram program(gl());
  std::vector<float> v;
  for (int x = 0; x < w; ++x) {
    const float val = (float(x) + 0.5f) / float(w);
    const float l = 2.0f * float(x) / float(w) - 1.0f, r = 2.0f * float(x + 1) / float(w) - 1.0f;
    const float q[36] = {l, -1, val, val, val, 1, r, -1, val, val, val, 1, r, 1, val, val, val, 1,
                         l, -1, val, val, val, 1, r, 1, val, val, val, 1, l, 1, val, val, val, 1};
    v.insert(v.end(), q, q + 36);
  }
  program.draw(v);
  const mp::Image img = target.resolve_and_read();
  double worst = 0;
  int not_rounded = 0;
  for (int x = 0; x < w; ++x) {
    const double val = double((float(x) + 0.5f) / float(w));
    const int got = img.pixel(x, 0)[0];
    worst = std::max(worst, std::abs(got - mp::linear_to_srgb(val) * 255.0));
    not_rounded += got != mp::linear_to_srgb8(val);
  }
  std::printf("%s sRGB encode: max error %.3f of a step, %d/%d not exactly rounded\n",
              std::string(backend_->name()).c_str(), worst, not_rounded, w);
  EXPECT_LE(worst, 0.65);
  EXPECT_LT(not_rounded, w / 8);
}

TEST_P(RenderTargetTest, NonSrgbTargetStoresValuesUnchanged) {
  mp::RenderTarget target(*backend_, {.width = 8, .height = 8, .srgb = false});
  mp::test::ColorProgram program(gl());
  program.rect_pixels(8, 8, 0, 0, 8, 8, 0.5f, 0.5f, 0.5f, 1.0f);
  EXPECT_EQ(target.resolve_and_read().pixel(4, 4)[0], 128);
}

TEST_P(RenderTargetTest, BlendingHappensInLinearSpace) {
  // White at 50 % over black: linear 0.5 -> stored 188 (gamma-space blending would store 128).
  mp::RenderTarget target(*backend_, {.width = 8, .height = 8, .samples = 4});
  gl().ClearColor(0, 0, 0, 1);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  gl().Enable(GL_BLEND);
  gl().BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  mp::test::ColorProgram program(gl());
  program.rect_pixels(8, 8, 0, 0, 8, 8, 1.0f, 1.0f, 1.0f, 0.5f);
  gl().Disable(GL_BLEND);
  const mp::Image img = target.resolve_and_read();
  const std::uint8_t* p = img.pixel(4, 4);
  EXPECT_NEAR(p[0], 188, 1);  // alpha 0.5 in 8-bit unorm is not exactly 0.5 on every path
  EXPECT_NEAR(p[1], 188, 1);
}

TEST_P(RenderTargetTest, DepthTestKeepsTheNearerSurface) {
  for (auto depth : {mp::DepthFormat::Depth24, mp::DepthFormat::Depth32F}) {
    for (int samples : {1, 4}) {
      SCOPED_TRACE(std::to_string(samples) + " samples, depth format " + std::to_string(int(depth)));
      mp::RenderTarget target(*backend_, {.width = 16, .height = 16, .samples = samples, .depth = depth,
                                          .srgb = false});
      const mp::Gl& g = gl();
      const GLuint program = mp::compile_program(g, R"(#version 300 es
layout(location = 0) in vec3 a_pos;
void main() { gl_Position = vec4(a_pos, 1.0); }
)",
                                                 R"(#version 300 es
precision highp float;
uniform vec4 u_color;
out vec4 o;
void main() { o = u_color; }
)",
                                                 "depth-test");
      GLuint vao = 0, vbo = 0;
      g.GenVertexArrays(1, &vao);
      g.GenBuffers(1, &vbo);
      g.BindVertexArray(vao);
      g.BindBuffer(GL_ARRAY_BUFFER, vbo);
      g.EnableVertexAttribArray(0);
      g.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      g.UseProgram(program);
      g.ClearColor(0, 0, 0, 1);
      g.ClearDepthf(1.0f);
      g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      g.Enable(GL_DEPTH_TEST);
      g.DepthFunc(GL_LESS);
      auto quad = [&](float z, float r, float gg) {
        const float v[18] = {-1, -1, z, 1, -1, z, 1, 1, z, -1, -1, z, 1, 1, z, -1, 1, z};
        g.BufferData(GL_ARRAY_BUFFER, sizeof v, v, GL_STREAM_DRAW);
        g.Uniform4f(g.GetUniformLocation(program, "u_color"), r, gg, 0, 1);
        g.DrawArrays(GL_TRIANGLES, 0, 6);
      };
      // Near first, then a surface 1e-4 behind it: the near one must stay (24-bit resolves it).
      quad(0.2f, 1, 0);
      quad(0.2001f, 0, 1);
      g.Disable(GL_DEPTH_TEST);
      const mp::Image img = target.resolve_and_read();
      const std::uint8_t* p = img.pixel(8, 8);
      EXPECT_EQ(p[0], 255);
      EXPECT_EQ(p[1], 0);
      g.DeleteBuffers(1, &vbo);
      g.DeleteVertexArrays(1, &vao);
      g.DeleteProgram(program);
      mp::check_gl(g, "depth test");
    }
  }
}

TEST_P(RenderTargetTest, CopyFromCopiesColourAndDepthOfEverySampleInTheRegions) {
  // Both llvmpipe backends have it (GLES 3.2 / GL 4.5); the engine's static layer depends on it.
  ASSERT_TRUE(gl().info.has_copy_image) << gl().info.version;
  for (int samples : {1, 4}) {
    SCOPED_TRACE("samples " + std::to_string(samples));
    const mp::RenderTargetOptions o{.width = 32, .height = 16, .samples = samples};
    mp::RenderTarget source(*backend_, o), target(*backend_, o);
    mp::test::ColorProgram program(gl());
    auto clear = [&](mp::RenderTarget& t, float r, float g, float b) {
      t.bind();
      gl().ClearColor(r, g, b, 1);
      gl().ClearDepthf(1.0f);
      gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    };
    // Source: a diagonal edge (partly covered pixels: only a per-sample copy keeps them) at depth 0.5.
    clear(source, 0.1f, 0.0f, 0.0f);
    gl().Enable(GL_DEPTH_TEST);
    gl().DepthFunc(GL_LESS);
    program.draw({-1, -1, 1, 1, 0, 1, 1, -1, 1, 1, 0, 1, -1, 1, 1, 1, 0, 1});
    clear(target, 0.0f, 0.0f, 1.0f);
    const mp::PixelRegion left{0, 0, 16, 16}, outside{40, 0, 8, 8};  // the second is clipped away
    const mp::PixelRegion regions[] = {left, outside};
    target.copy_from(source, regions);
    // A full-screen draw at the same depth 0.5 with GL_LESS: rejected exactly where copied depth
    // is 0.5, so it also shows the depth was copied (cleared depth 1 lets it through).
    for (mp::RenderTarget* t : {&source, &target}) {
      t->bind();
      program.draw({-1, -1, 0, 1, 0, 1, 3, -1, 0, 1, 0, 1, -1, 3, 0, 1, 0, 1});
    }
    gl().Disable(GL_DEPTH_TEST);
    const mp::Image a = source.resolve_and_read(), b = target.resolve_and_read();
    int differing_left = 0, not_green_right = 0, edge_pixels = 0;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 32; ++x) {
        const std::uint8_t* p = a.pixel(x, y);
        const std::uint8_t* q = b.pixel(x, y);
        if (x < 16) {
          differing_left += std::memcmp(p, q, 4) != 0;
          edge_pixels += p[0] > 0 && p[0] < 255;  // mixed: yellow triangle and green samples
        } else {
          not_green_right += !(q[0] == 0 && q[1] == 255 && q[2] == 0);
        }
      }
    EXPECT_EQ(differing_left, 0);
    EXPECT_EQ(not_green_right, 0);
    if (samples > 1) {
      EXPECT_GT(edge_pixels, 4);
    }
  }
  mp::RenderTarget a(*backend_, {.width = 8, .height = 8, .samples = 4}), other_size(*backend_, {.width = 8, .height = 9, .samples = 4}),
      other_samples(*backend_, {.width = 8, .height = 8, .samples = 1});
  const mp::PixelRegion all{0, 0, 8, 8};
  EXPECT_THROW(a.copy_from(other_size, std::span(&all, 1)), std::invalid_argument);
  EXPECT_THROW(a.copy_from(other_samples, std::span(&all, 1)), std::invalid_argument);
}

TEST_P(RenderTargetTest, ReadRegionsGivesTheFullReadsPixelsOfEachBoxOnly) {
  for (int samples : {1, 4}) {
    SCOPED_TRACE("samples " + std::to_string(samples));
    mp::RenderTarget target(*backend_, {.width = 48, .height = 24, .samples = samples});
    mp::test::ColorProgram program(gl());
    gl().ClearColor(0.05f, 0.1f, 0.2f, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    // A diagonal edge (mixed MSAA pixels) and two rectangles: every box below sees varied pixels.
    program.draw({-1, -1, 1, 0.5f, 0, 1, 1, -1, 0, 1, 0.5f, 1, -1, 1, 0.5f, 0, 1, 1});
    program.rect_pixels(48, 24, 30, 2, 44, 9, 1, 1, 1, 1);
    const mp::PixelRegion boxes[] = {{3, 4, 10, 7}, {28, 14, 17, 9}, {40, 20, 20, 20}, {60, 0, 4, 4}};
    const std::vector<mp::Image> parts = target.read_regions(boxes);
    const mp::Image full = target.resolve_and_read();
    ASSERT_EQ(parts.size(), 4u);
    // The third box is clipped to the target (8 x 4); the fourth lies outside it.
    const mp::PixelRegion clipped[] = {boxes[0], boxes[1], {40, 20, 8, 4}, {0, 0, 0, 0}};
    for (std::size_t i = 0; i < 4; ++i) {
      SCOPED_TRACE("box " + std::to_string(i));
      const mp::PixelRegion& c = clipped[i];
      ASSERT_EQ(parts[i].width, c.width);
      ASSERT_EQ(parts[i].height, c.height);
      int differing = 0;
      for (int y = 0; y < c.height; ++y)  // region rows top-down; GL y counts from the bottom
        for (int x = 0; x < c.width; ++x)
          differing += std::memcmp(parts[i].pixel(x, y), full.pixel(c.x + x, 24 - c.y - c.height + y), 4) != 0;
      EXPECT_EQ(differing, 0);
    }
  }
}

TEST_P(RenderTargetTest, ReadRegionsResolvesItsBoxesAndAnEmptyListTouchesNothing) {
  mp::RenderTarget target(*backend_, {.width = 16, .height = 16, .samples = 4, .srgb = false});
  gl().ClearColor(1, 0, 0, 1);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  EXPECT_EQ(target.resolve_and_read(), mp::Image(16, 16, 255, 0, 0));
  target.bind();
  gl().ClearColor(0, 1, 0, 1);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  // Nothing listed: nothing resolved, so the resolved image still holds the red frame.
  EXPECT_TRUE(target.read_regions({}).empty());
  EXPECT_EQ(target.read_resolved(), mp::Image(16, 16, 255, 0, 0));
  // One box: read green, and only that box resolved (the rest of the resolved image stays red).
  const mp::PixelRegion box{4, 4, 4, 4};
  const auto parts = target.read_regions(std::span(&box, 1));
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0], mp::Image(4, 4, 0, 255, 0));
  const mp::Image resolved = target.read_resolved();
  EXPECT_EQ(resolved.pixel(5, 16 - 6)[1], 255);
  EXPECT_EQ(resolved.pixel(0, 0)[0], 255);
}

TEST_P(RenderTargetTest, SamplesAreValidatedAndClamped) {
  EXPECT_THROW(mp::RenderTarget(*backend_, {.width = 8, .height = 8, .samples = 3}), std::invalid_argument);
  EXPECT_THROW(mp::RenderTarget(*backend_, {.width = 0, .height = 8}), std::invalid_argument);
  EXPECT_THROW(mp::RenderTarget(*backend_, {.width = 8, .height = 1 << 20}), std::invalid_argument);
  mp::RenderTarget target(*backend_, {.width = 8, .height = 8, .samples = 8});
  const int max = gl().info.max_samples;
  EXPECT_EQ(target.samples(), std::min(8, max));
  EXPECT_EQ(target.warning().empty(), max >= 8) << target.warning();
}

TEST_P(RenderTargetTest, MovedTargetKeepsWorking) {
  mp::RenderTarget a(*backend_, {.width = 4, .height = 4, .srgb = false});
  mp::RenderTarget b = std::move(a);
  b.bind();
  gl().ClearColor(1, 0, 1, 1);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  EXPECT_EQ(b.resolve_and_read(), mp::Image(4, 4, 255, 0, 255, 255));
  EXPECT_THROW(a.bind(), std::logic_error);  // NOLINT(bugprone-use-after-move): the contract under test
}

namespace {

// A small scene with what differs between drivers if anything does: interpolated colours,
// overlapping alpha blending, antialiased edges, sRGB encode, MSAA resolve.
mp::Image render_reference_scene(mp::GpuBackend& backend) {
  const int w = 320, h = 200;
  mp::RenderTarget target(backend, {.width = w, .height = h, .samples = 4});
  const mp::Gl& gl = backend.gl();
  mp::test::ColorProgram program(gl);
  gl.ClearColor(0.02f, 0.03f, 0.05f, 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.Enable(GL_BLEND);
  gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  program.draw({-0.95f, -0.9f, 1, 0, 0, 1, 0.8f, -0.6f, 0, 1, 0, 1, -0.3f, 0.95f, 0, 0, 1, 1});
  program.draw({-0.5f, 0.7f, 1, 1, 1, 0.6f, 0.9f, 0.9f, 1, 0.5f, 0, 0.3f, 0.4f, -0.95f, 0, 0.8f, 1, 0.8f});
  for (int i = 0; i < 12; ++i) {  // thin "needles" at many angles: edge coverage everywhere
    const float a = 0.26f * float(i), c = std::cos(a), s = std::sin(a);
    program.draw({0, 0, 1, 0.2f, 0.1f, 0.9f, 0.9f * c - 0.02f * s, 0.9f * s + 0.02f * c, 1, 0.9f, 0.1f, 0.9f,
                  0.9f * c + 0.02f * s, 0.9f * s - 0.02f * c, 1, 0.9f, 0.1f, 0.9f});
  }
  gl.Disable(GL_BLEND);
  return target.resolve_and_read();
}

}  // namespace

TEST(CrossBackend, EglAndOSMesaRenderTheSameImage) {
  mp::Image egl_image, osmesa_image;
  {
    auto egl = mp::create_backend(BackendKind::Egl);
    egl_image = render_reference_scene(*egl);
  }
  {
    auto osmesa = mp::create_backend(BackendKind::OSMesa);
    osmesa_image = render_reference_scene(*osmesa);
  }
  const double db = mp::psnr(egl_image, osmesa_image);
  std::printf("EGL vs OSMesa: PSNR %.2f dB, SSIM %.6f\n", db, mp::ssim(egl_image, osmesa_image));
  EXPECT_GE(db, 50.0);  // the artist's preview equals the target: PSNR >= 50 dB
  // The scene is not trivially empty: most pixels differ from the clear colour.
  const auto bg = [](double linear) { return static_cast<std::uint8_t>(mp::linear_to_srgb8(linear)); };
  const mp::Mask drawn = mp::object_mask(egl_image, {bg(0.02), bg(0.03), bg(0.05)}, 2);
  EXPECT_GT(drawn.count(), 320u * 200u / 4);
}

TEST(CrossBackend, BothContextsAliveAndSwitched) {
  // One process holding both an EGL and an OSMesa context: the function tables keep each call on
  // the right implementation as long as the caller makes the backend current first.
  auto egl = mp::create_backend(BackendKind::Egl);
  auto osmesa = mp::create_backend(BackendKind::OSMesa);  // now current
  const mp::Image first_osmesa = render_reference_scene(*osmesa);
  egl->make_current();
  const mp::Image first_egl = render_reference_scene(*egl);
  osmesa->make_current();
  EXPECT_EQ(render_reference_scene(*osmesa), first_osmesa);  // deterministic
  egl->make_current();
  EXPECT_EQ(render_reference_scene(*egl), first_egl);
  EXPECT_GE(mp::psnr(first_egl, first_osmesa), 50.0);
}
