// The film filter resolve (resolve_filter.hpp): the kernel and its weights as numbers, and on both
// backends the resolve of a half-plane edge against the analytic ramp, a region resolve against
// the full one, and the box default against a plain glBlitFramebuffer, byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "gl_test_util.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/resolve_filter.hpp"

namespace mp = meter::platform;
using mp::BackendKind;
using Kind = mp::ResolveFilter::Kind;

namespace {

const mp::ResolveFilter kFilm{Kind::BlackmanHarris, 1.5};

// EEVEE's film filter over a straight edge: the share of the kernel's mass at offsets below t
// (pixels) in one axis, the integral of the Blackman-Harris window of radius r in closed form.
double film_cdf(double t, double r) {
  if (t <= -r) return 0.0;
  if (t >= r) return 1.0;
  const double a0 = 0.35875, a1 = 0.48829, a2 = 0.14128, a3 = 0.01168, pi = std::numbers::pi;
  return 0.5 + t / (2.0 * r) + a1 / (2.0 * pi * a0) * std::sin(pi * t / r) + a2 / (4.0 * pi * a0) * std::sin(2.0 * pi * t / r) +
         a3 / (6.0 * pi * a0) * std::sin(3.0 * pi * t / r);
}

}  // namespace

TEST(ResolveFilterWeights, KernelIsBlackmanHarrisOfTheRadius) {
  EXPECT_NEAR(mp::blackman_harris(0.0, 1.5), 1.0, 1e-12);
  EXPECT_NEAR(mp::blackman_harris(1.5, 1.5), 0.0, 1e-12);
  EXPECT_EQ(mp::blackman_harris(2.0, 1.5), 0.0);
  EXPECT_DOUBLE_EQ(mp::blackman_harris(-0.7, 1.5), mp::blackman_harris(0.7, 1.5));
  // Half way out: 0.35875 + 0.14128 cos(pi) = 0.21747 (the odd terms vanish at x = 3 pi / 2).
  EXPECT_NEAR(mp::blackman_harris(0.75, 1.5), 0.21747, 1e-12);
}

TEST(ResolveFilterWeights, ReachAndNormalization) {
  EXPECT_EQ(mp::filter_reach_px({}), 0);
  EXPECT_EQ(mp::filter_reach_px({Kind::BlackmanHarris, 0.5}), 0);   // samples within 0.5 px: own pixel only
  EXPECT_EQ(mp::filter_reach_px({Kind::BlackmanHarris, 1.5}), 1);   // 3 x 3 pixels
  EXPECT_EQ(mp::filter_reach_px({Kind::BlackmanHarris, 1.6}), 2);   // a neighbour's far samples reach past 1.5
  EXPECT_EQ(mp::filter_reach_px({Kind::BlackmanHarris, 3.0}), 3);
  const std::vector<std::array<float, 2>> four = {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}};
  const std::vector<float> box = mp::resolve_weights({}, four);
  EXPECT_EQ(box, (std::vector<float>{0.25f, 0.25f, 0.25f, 0.25f}));
  const std::vector<float> film = mp::resolve_weights(kFilm, four);
  ASSERT_EQ(film.size(), 9u * 4u);
  double sum = 0;
  for (float w : film) {
    EXPECT_GE(w, 0.0f);
    sum += w;
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  // The 8 samples nearest the far corners weigh under kNegligibleWeight each: left out.
  EXPECT_EQ(std::count(film.begin(), film.end(), 0.0f), 8);
  // The centre pixel's samples (index 4 of the 3 x 3) carry most of the weight, the corners least.
  double centre = 0, corner = 0;
  for (int s = 0; s < 4; ++s) centre += film[4 * 4 + s], corner += film[0 * 4 + s];
  EXPECT_GT(centre, 0.3);
  EXPECT_LT(corner, 0.02);
}

class ResolveFilterGl : public mp::test::GlBackendTest {};

INSTANTIATE_TEST_SUITE_P(Both, ResolveFilterGl, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

// White (linear 1) left of a vertical edge at x = 20.3 px, black right of it, on an sRGB target.
TEST_P(ResolveFilterGl, HalfPlaneEdgeGivesTheFilmFiltersRamp) {
  constexpr int W = 48, H = 8;
  constexpr double edge = 20.3;
  auto draw_edge = [&](const mp::ResolveFilter& filter) {
    mp::RenderTarget target(*backend_, {.width = W, .height = H, .samples = 4, .depth = mp::DepthFormat::None, .resolve = filter});
    EXPECT_EQ(target.resolve_filter(), filter);
    mp::test::ColorProgram program(gl());
    gl().ClearColor(0, 0, 0, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT);
    const float x = float(2.0 * edge / W - 1.0);
    program.draw({-1, -1, 1, 1, 1, 1, x, -1, 1, 1, 1, 1, x, 1, 1, 1, 1, 1, -1, -1, 1, 1, 1, 1, x, 1, 1, 1, 1, 1, -1, 1, 1, 1, 1, 1});
    return std::pair{target.resolve_and_read(), mp::test::sample_positions(gl(), target)};
  };
  const auto [img, positions] = draw_edge(kFilm);
  ASSERT_EQ(positions.size(), 4u);
  const std::vector<float> w = mp::resolve_weights(kFilm, positions);

  // (1) Exactly the filter's weighted sum of the covered samples, in linear light: the 8-bit value
  // is the sRGB encode of that sum, within 1 level (the encode's rounding and float sums).
  // (2) The continuous film filter (EEVEE's limit of many TAA samples, film_cdf): 4 samples per
  // pixel make the ramp a staircase over 12 sample columns 1/4 px apart. The bound is that
  // staircase's own distance from the continuous ramp at each pixel (computed from the weights,
  // no GL) plus the 8-bit step near the value: what is left is the GPU's error alone.
  double worst_film = 0;
  for (int x = 14; x < 27; ++x) {
    SCOPED_TRACE("pixel column " + std::to_string(x));
    double expected = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        for (int s = 0; s < 4; ++s)
          if (x + dx + positions[std::size_t(s)][0] < edge) expected += w[std::size_t(((dy + 1) * 3 + dx + 1) * 4 + s)];
    for (int y = 0; y < H; ++y) EXPECT_NEAR(img.pixel(x, y)[0], mp::linear_to_srgb8(expected), 1) << "row " << y;
    const double got = mp::srgb_to_linear(img.pixel(x, H / 2)[0] / 255.0);
    const double analytic = film_cdf(edge - (x + 0.5), kFilm.width_px);
    const double level = mp::srgb_to_linear(std::min(1.0, (img.pixel(x, H / 2)[0] + 1) / 255.0)) - got;
    EXPECT_NEAR(got, analytic, std::abs(expected - analytic) + level);
    EXPECT_LT(std::abs(expected - analytic), 0.06);  // the 4-sample staircase: measured 0.037 at worst
    worst_film = std::max(worst_film, std::abs(got - analytic));
  }
  // The ramp reaches past the edge's pixel: its neighbours on both sides are partly lit, which a
  // box resolve never does (pixel 19 lies fully left of the edge, pixel 21 fully right).
  EXPECT_LT(img.pixel(19, 0)[0], 255);
  EXPECT_GT(img.pixel(21, 0)[0], 0);
  // The box resolve of the same edge is further from the film's ramp (about twice, measured 0.070
  // against 0.037): the comparison above tells the two apart.
  const auto [boxed, box_positions] = draw_edge(mp::ResolveFilter{});
  double worst_box = 0;
  for (int x = 14; x < 27; ++x)
    worst_box = std::max(worst_box, std::abs(mp::srgb_to_linear(boxed.pixel(x, H / 2)[0] / 255.0) -
                                             film_cdf(edge - (x + 0.5), kFilm.width_px)));
  EXPECT_GT(worst_box, 1.5 * worst_film);
}

// A partial redraw resolves only its region: the result must equal a full resolve of the same
// samples everywhere, including the pixels within the filter's reach outside the region.
TEST_P(ResolveFilterGl, RegionResolveEqualsTheFullResolve) {
  constexpr int W = 64, H = 40;
  const mp::PixelRegion region{24, 12, 10, 9};  // GL window coordinates
  auto draw = [&](mp::RenderTarget& t, mp::test::ColorProgram& program, bool partial) {
    gl().ClearColor(0.1f, 0.1f, 0.1f, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    program.draw({-0.9f, -0.8f, 1, 0.5f, 0, 1, 0.8f, -0.3f, 1, 0.5f, 0, 1, -0.1f, 0.9f, 1, 0.5f, 0, 1});
    const mp::PixelRegion all{0, 0, W, H};
    if (partial) t.resolve(std::span(&all, 1));
    // The change: a thin bright sliver inside the region, touching its first row and column (so
    // the filter carries it into the pixels just outside). Its geometry stays inside, as the
    // engine's damage boxes (1 px beyond a draw's extent) keep it: llvmpipe's scissor under MSAA
    // lets a draw that crosses the box write samples of the row and column just outside it.
    auto ndc = [&](double x, double y) { return std::pair{float(2.0 * x / W - 1.0), float(2.0 * y / H - 1.0)}; };
    const auto [ax, ay] = ndc(24.3, 12.2);
    const auto [bx, by] = ndc(25.0, 12.2);
    const auto [cx, cy] = ndc(33.5, 20.6);
    gl().Enable(GL_SCISSOR_TEST);
    gl().Scissor(region.x, region.y, region.width, region.height);
    program.draw({ax, ay, 1, 1, 1, 1, bx, by, 1, 1, 1, 1, cx, cy, 1, 1, 1, 1});
    gl().Disable(GL_SCISSOR_TEST);
    if (partial) t.resolve(std::span(&region, 1));
    else t.resolve(std::span(&all, 1));
    return t.read_resolved();
  };
  mp::RenderTarget a(*backend_, {.width = W, .height = H, .samples = 4, .resolve = kFilm});
  mp::RenderTarget b(*backend_, {.width = W, .height = H, .samples = 4, .resolve = kFilm});
  EXPECT_EQ(a.resolve_margin_px(), 1);
  mp::test::ColorProgram program(gl());
  a.bind();
  const mp::Image partial = draw(a, program, true);
  b.bind();
  const mp::Image full = draw(b, program, false);
  ASSERT_EQ(partial.width, full.width);
  int differing = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 4; ++c) differing += partial.pixel(x, y)[c] != full.pixel(x, y)[c];
  EXPECT_EQ(differing, 0);
  // read_regions (the integrity monitor's readback) resolves and reads the same pixels.
  const std::vector<mp::Image> boxes = a.read_regions(std::span(&region, 1));
  ASSERT_EQ(boxes.size(), 1u);
  for (int y = 0; y < region.height; ++y)
    for (int x = 0; x < region.width; ++x)
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(boxes[0].pixel(x, y)[c], full.pixel(region.x + x, H - region.y - region.height + y)[c]) << x << "," << y;
}

// The default target's box resolve, a shader pass where multisample textures exist, gives exactly
// the bytes of a glBlitFramebuffer of a multisample renderbuffer the test makes itself, and so does
// the target asked to blit (the benchmarks' baseline), whole and region by region.
TEST_P(ResolveFilterGl, BoxDefaultIsThePlainBlitByteForByte) {
  constexpr int W = 40, H = 24;
  EXPECT_EQ(mp::RenderTargetOptions{}.resolve.kind, Kind::Box);
  const std::vector<float> tri = {-0.9f, -0.7f, 1, 0.3f, 0.6f, 1, 0.85f, -0.2f, 0.2f, 1, 0.4f, 1, -0.3f, 0.95f, 0.9f, 0.1f, 1, 1};
  mp::test::ColorProgram program(gl());
  const mp::PixelRegion box{3, 5, 17, 11};
  auto draw_and_read = [&](bool by_blit, std::vector<mp::Image>* region) {
    mp::RenderTarget target(*backend_, {.width = W, .height = H, .samples = 4, .depth = mp::DepthFormat::None,
                                        .box_resolve_by_blit = by_blit});
    EXPECT_EQ(target.resolve_margin_px(), 0);
    EXPECT_EQ(target.resolves_by_shader(), !by_blit && gl().info.has_multisample_texture);
    gl().ClearColor(0, 0, 0, 1);
    gl().Clear(GL_COLOR_BUFFER_BIT);
    program.draw(tri);
    *region = target.read_regions(std::span(&box, 1));
    return target.resolve_and_read();
  };
  std::vector<mp::Image> ours_box, blit_box;
  const mp::Image ours = draw_and_read(false, &ours_box);
  const mp::Image blit = draw_and_read(true, &blit_box);
  ASSERT_EQ(ours.rgba, blit.rgba);
  ASSERT_EQ(ours_box.size(), 1u);
  ASSERT_EQ(blit_box.size(), 1u);
  EXPECT_EQ(ours_box[0].rgba, blit_box[0].rgba);
  for (int y = 0; y < box.height; ++y)  // the region read equals the whole resolve's pixels there
    for (int x = 0; x < box.width; ++x)
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(ours_box[0].pixel(x, y)[c], ours.pixel(box.x + x, H - box.y - box.height + y)[c]) << x << "," << y;

  GLuint rb = 0, tex = 0, ms = 0, ss = 0;
  gl().GenRenderbuffers(1, &rb);
  gl().BindRenderbuffer(GL_RENDERBUFFER, rb);
  gl().RenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_SRGB8_ALPHA8, W, H);
  gl().GenFramebuffers(1, &ms);
  gl().BindFramebuffer(GL_FRAMEBUFFER, ms);
  gl().FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
  gl().GenTextures(1, &tex);
  gl().BindTexture(GL_TEXTURE_2D, tex);
  gl().TexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, W, H);
  gl().GenFramebuffers(1, &ss);
  gl().BindFramebuffer(GL_FRAMEBUFFER, ss);
  gl().FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
  gl().BindFramebuffer(GL_FRAMEBUFFER, ms);
  gl().Viewport(0, 0, W, H);
  if (gl().info.needs_framebuffer_srgb_enable) gl().Enable(GL_FRAMEBUFFER_SRGB);
  gl().Clear(GL_COLOR_BUFFER_BIT);
  program.draw(tri);
  gl().BindFramebuffer(GL_READ_FRAMEBUFFER, ms);
  gl().BindFramebuffer(GL_DRAW_FRAMEBUFFER, ss);
  gl().BlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl().BindFramebuffer(GL_READ_FRAMEBUFFER, ss);
  mp::Image theirs(W, H);
  gl().ReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, theirs.rgba.data());
  mp::check_gl(gl(), "plain blit resolve");
  gl().DeleteFramebuffers(1, &ms);
  gl().DeleteFramebuffers(1, &ss);
  gl().DeleteRenderbuffers(1, &rb);
  gl().DeleteTextures(1, &tex);
  for (int y = 0; y < H; ++y)  // ReadPixels rows are bottom-up
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(ours.pixel(x, H - 1 - y)[c], theirs.pixel(x, y)[c]) << x << "," << y;
  int partial = 0;  // the triangle's edges are anti-aliased: the comparison covers blended pixels
  for (int i = 0; i < W * H; ++i) partial += ours.rgba[std::size_t(i) * 4 + 1] > 0 && ours.rgba[std::size_t(i) * 4 + 1] < 250;
  EXPECT_GT(partial, 10);
}

TEST_P(ResolveFilterGl, BadWidthAndNoSamplesAreSaid) {
  EXPECT_THROW(mp::RenderTarget(*backend_, {.width = 8, .height = 8, .samples = 4, .resolve = {Kind::BlackmanHarris, 0.2}}),
               std::invalid_argument);
  EXPECT_THROW(mp::RenderTarget(*backend_, {.width = 8, .height = 8, .samples = 4, .resolve = {Kind::BlackmanHarris, 3.5}}),
               std::invalid_argument);
  mp::RenderTarget single(*backend_, {.width = 8, .height = 8, .samples = 1, .resolve = kFilm});
  EXPECT_EQ(single.resolve_filter().kind, Kind::Box);
  EXPECT_NE(single.warning().find("1 sample per pixel"), std::string::npos) << single.warning();
}

// The static layer's copy works between film targets (multisample textures), every sample.
TEST_P(ResolveFilterGl, CopyFromBetweenFilmTargetsKeepsEverySample) {
  constexpr int W = 32, H = 16;
  mp::RenderTarget source(*backend_, {.width = W, .height = H, .samples = 4, .resolve = kFilm});
  mp::test::ColorProgram program(gl());
  gl().ClearColor(0, 0, 0, 1);
  gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  program.draw({-0.9f, -0.9f, 0, 1, 0, 1, 0.9f, -0.5f, 0, 1, 0, 1, 0.1f, 0.9f, 0, 1, 0, 1});
  const mp::Image want = source.resolve_and_read();
  mp::RenderTarget copy(*backend_, {.width = W, .height = H, .samples = 4, .resolve = kFilm});
  gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const mp::PixelRegion all{0, 0, W, H};
  copy.copy_from(source, std::span(&all, 1));
  EXPECT_EQ(copy.resolve_and_read(), want);
}
