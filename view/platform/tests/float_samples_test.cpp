// Half-float MSAA samples (RenderTargetOptions::sample_format): light above white survives until
// the resolve has filtered it. On both backends, an edge of linear radiance 3 on black: with 8-bit
// samples each covered sample holds white, with RGBA16F samples it holds 3 and the resolved pixel
// is min(1, 3 x the covered share), the film of a float renderer; light at or below white resolves
// the same either way; the layer copy and the options' checks know the format.
#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <stdexcept>
#include <vector>

#include "gl_test_util.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/resolve_filter.hpp"

namespace mp = meter::platform;
using mp::BackendKind;
using mp::SampleFormat;
using Kind = mp::ResolveFilter::Kind;

namespace {

class FloatSamplesGl : public mp::test::GlBackendTest {};

INSTANTIATE_TEST_SUITE_P(Both, FloatSamplesGl, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

constexpr int W = 48, H = 8;
constexpr double kEdge = 20.3;  // the lit half-plane ends here (pixels from the left)

struct Drawn {
  mp::Image image;
  std::vector<float> weights;  // the resolve's weight of each sample of the 3 x 3 neighbourhood
  std::vector<std::array<float, 2>> positions;
};

// The half-plane left of kEdge in linear radiance `value` (all channels), black right of it.
Drawn draw_edge(mp::GpuBackend& backend, const mp::Gl& gl, const mp::ResolveFilter& filter, SampleFormat format,
                float value) {
  mp::RenderTarget target(backend, {.width = W, .height = H, .samples = 4, .depth = mp::DepthFormat::None,
                                    .resolve = filter, .sample_format = format});
  EXPECT_EQ(target.sample_format(), format);
  EXPECT_TRUE(target.resolves_by_shader() || format == SampleFormat::Srgb8);
  mp::test::ColorProgram program(gl);
  gl.ClearColor(0, 0, 0, 1);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  const float x = float(2.0 * kEdge / W - 1.0), v = value;
  program.draw({-1, -1, v, v, v, 1, x, -1, v, v, v, 1, x, 1, v, v, v, 1, -1, -1, v, v, v, 1, x, 1, v, v, v, 1, -1, 1, v, v, v, 1});
  Drawn d;
  d.positions = mp::test::sample_positions(gl, target);
  d.image = target.resolve_and_read();
  if (filter.kind == Kind::BlackmanHarris) {
    d.weights = mp::resolve_weights(filter, d.positions);
  } else {  // the box: each of the pixel's own samples a quarter, nothing from the neighbours
    d.weights.assign(9 * 4, 0.0f);
    for (int s = 0; s < 4; ++s) d.weights[std::size_t(4 * 4 + s)] = 0.25f;
  }
  return d;
}

// The linear value the resolve gives pixel column x when every covered sample holds `stored`.
double expected_linear(const Drawn& d, int x, double stored) {
  double sum = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      for (int s = 0; s < 4; ++s)
        if (x + dx + d.positions[std::size_t(s)][0] < kEdge) sum += d.weights[std::size_t(((dy + 1) * 3 + dx + 1) * 4 + s)];
  return sum * stored;
}

TEST_P(FloatSamplesGl, LightAboveWhiteIsClampedAfterTheFilterNotPerSample) {
  for (const mp::ResolveFilter& filter : {mp::ResolveFilter{}, mp::ResolveFilter{Kind::BlackmanHarris, 1.5}}) {
    SCOPED_TRACE(mp::to_string(filter.kind));
    const Drawn eight = draw_edge(*backend_, gl(), filter, SampleFormat::Srgb8, 3.0f);
    const Drawn half = draw_edge(*backend_, gl(), filter, SampleFormat::Rgba16f, 3.0f);
    int brighter = 0;
    for (int x = 16; x < 25; ++x) {
      SCOPED_TRACE("pixel column " + std::to_string(x));
      // Within one 8-bit level of the encode of the exact sum (its rounding and float sums).
      const int want8 = mp::linear_to_srgb8(std::min(1.0, expected_linear(eight, x, 1.0)));
      const int want16 = mp::linear_to_srgb8(std::min(1.0, expected_linear(half, x, 3.0)));
      for (int y = 0; y < H; ++y) {
        EXPECT_NEAR(eight.image.pixel(x, y)[0], want8, 1) << "8-bit samples, row " << y;
        EXPECT_NEAR(half.image.pixel(x, y)[0], want16, 1) << "half-float samples, row " << y;
      }
      brighter += half.image.pixel(x, 0)[0] > eight.image.pixel(x, 0)[0] + 8;
    }
    // The edge's partly covered pixels are the ones that differ: at least the pixel the edge
    // crosses (covered 0.3: 0.3 of white against 0.9), more under the film filter's reach.
    EXPECT_GE(brighter, 1);
  }
}

TEST_P(FloatSamplesGl, LightUpToWhiteResolvesAsWithEightBitSamples) {
  for (const mp::ResolveFilter& filter : {mp::ResolveFilter{}, mp::ResolveFilter{Kind::BlackmanHarris, 1.5}}) {
    SCOPED_TRACE(mp::to_string(filter.kind));
    const Drawn eight = draw_edge(*backend_, gl(), filter, SampleFormat::Srgb8, 0.6f);
    const Drawn half = draw_edge(*backend_, gl(), filter, SampleFormat::Rgba16f, 0.6f);
    ASSERT_EQ(eight.image.rgba.size(), half.image.rgba.size());
    // One level: 8-bit samples store 0.6 sRGB-rounded, half floats to 11 bits.
    for (std::size_t i = 0; i < eight.image.rgba.size(); ++i)
      ASSERT_NEAR(eight.image.rgba[i], half.image.rgba[i], 1) << "byte " << i;
  }
}

TEST_P(FloatSamplesGl, CopyNeedsTheSameFormatAndSingleSampleTargetsSayTheyHaveNone) {
  const mp::RenderTargetOptions half{.width = 16, .height = 8, .samples = 4, .sample_format = SampleFormat::Rgba16f};
  mp::RenderTargetOptions eight = half;
  eight.sample_format = SampleFormat::Srgb8;
  mp::RenderTarget a(*backend_, half), b(*backend_, half), c(*backend_, eight);
  const mp::PixelRegion all{0, 0, 16, 8};
  EXPECT_NO_THROW(b.copy_from(a, std::span(&all, 1)));  // the static layer's copy, sample for sample
  try {
    c.copy_from(a, std::span(&all, 1));
    ADD_FAILURE() << "a copy between 8-bit and half-float samples was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("RGBA16F"), std::string::npos) << e.what();
  }
  mp::RenderTargetOptions single = half;
  single.samples = 1;
  mp::RenderTarget s(*backend_, single);
  EXPECT_EQ(s.sample_format(), SampleFormat::Srgb8);
  EXPECT_NE(s.warning().find("1 sample per pixel"), std::string::npos) << s.warning();
  // Asking for the blit does not take the float samples' resolve away from the shader pass.
  mp::RenderTargetOptions blit = half;
  blit.box_resolve_by_blit = true;
  EXPECT_TRUE(mp::RenderTarget(*backend_, blit).resolves_by_shader());
}

}  // namespace
