// A texture's mip chain made on the CPU instead of by glGenerateMipmap. On llvmpipe the driver's
// mipmap pass is a blit whose shaders LLVM compiles in every process, warm shader cache or not: for
// the cluster's one 256x256 texture that was 240-440 ms of every start on the loaded 2-core
// development machine (bench/budget). Where llvmpipe's result is known exactly (8-bit linear RGBA,
// power-of-two sides: each level the rounded mean of two neighbours across, then of two rows down,
// checked against glGenerateMipmap texel for texel by texture_mips_render_test) the CPU chain is
// that result; sRGB or other sizes keep glGenerateMipmap. On a GPU driver the chain is a 2x2 box,
// one of the filters glGenerateMipmap may use.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace meter::engine {

// Whether box_mip_chain stands in for glGenerateMipmap on a texture of this size and encoding.
bool box_mips_apply(int width, int height, bool srgb);

// Levels 1..n (down to 1x1) of a width x height RGBA8 image (rows in upload order); level k is
// max(1, width >> k) x max(1, height >> k). Requires box_mips_apply(width, height, false).
std::vector<std::vector<std::uint8_t>> box_mip_chain(std::span<const std::uint8_t> rgba, int width, int height);

}  // namespace meter::engine
