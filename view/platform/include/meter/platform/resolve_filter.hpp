// How a multisample target becomes one colour per pixel (the MSAA resolve), and the film filter's
// weights as plain numbers (no GL: the shader pass that applies them is the render target's).
//
//   Box             every sample of the pixel, equal weights (glBlitFramebuffer): the default and
//                   the fast path; an edge stays inside the pixel it crosses.
//   BlackmanHarris  Blender EEVEE's film filter: each output pixel is the weighted mean of the
//                   samples of its neighbourhood, weight = bh(dx / (2 r)) * bh(dy / (2 r)) of the
//                   sample's offset (dx, dy) from the pixel centre, r = width_px, bh the 4-term
//                   Blackman-Harris window on [-1/2, 1/2]. EEVEE (2.8 .. 3.x) jitters its TAA samples
//                   by the inverse CDF of that window scaled to [-filter_size, filter_size] pixels
//                   in x and in y independently (eevee_temporal_sampling.c), and averages them: the
//                   same separable kernel, 2 r pixels wide, 1.5 px = 3 px across by default. An edge
//                   is then spread over about three pixels, as in the authoring tool.
//
// Weights are applied in linear light (an sRGB target's samples are decoded on fetch and the
// result encoded on write), like the box resolve.
#pragma once

#include <array>
#include <span>
#include <vector>

namespace meter::platform {

struct ResolveFilter {
  enum class Kind { Box, BlackmanHarris };
  Kind kind = Kind::Box;
  // Blackman-Harris radius in output pixels (Blender's Film > Filter Size). Allowed range:
  // kMinWidthPx .. kMaxWidthPx (std::invalid_argument otherwise, from the render target).
  double width_px = 1.5;
  static constexpr double kMinWidthPx = 0.5;
  static constexpr double kMaxWidthPx = 3.0;
  bool operator==(const ResolveFilter&) const = default;
};

// "box" | "blackman-harris".
const char* to_string(ResolveFilter::Kind kind);

// The 4-term Blackman-Harris window at `offset` pixels from the centre of a window `radius`
// pixels wide on each side: 1 at 0, 0 at +-radius and beyond.
double blackman_harris(double offset, double radius);

// How many whole pixels beyond a pixel its resolve reads (0 for Box): a sample at offset d
// inside a neighbour k pixels away can lie within the radius when k - 1/2 < r.
// A resolved pixel changes when a sample up to this many pixels away changes, so a redrawn region
// must be resolved with this margin around it.
int filter_reach_px(const ResolveFilter& filter);

// Normalized weights (sum 1) of every sample of the (2 k + 1)^2 neighbourhood, k =
// filter_reach_px(filter), for samples at `positions` in every pixel ([0, 1)^2 within the pixel,
// origin bottom-left, as glGetMultisamplefv(GL_SAMPLE_POSITION) gives them). Layout: neighbour row dy = -k..k
// (outer), column dx = -k..k, then sample index: weights[((dy + k) * (2 k + 1) + dx + k) * n + s].
// Box: k = 0, weights 1/n. Weights under kNegligibleWeight of the total are 0 (the resolve pass
// does not fetch those samples): at 1.5 px and MSAA 4, 8 of the 36 corner samples, together 1.4e-4 of
// the kernel, under half an 8-bit level even next to black in sRGB.
constexpr double kNegligibleWeight = 1e-4;
std::vector<float> resolve_weights(const ResolveFilter& filter, std::span<const std::array<float, 2>> positions);

}  // namespace meter::platform
