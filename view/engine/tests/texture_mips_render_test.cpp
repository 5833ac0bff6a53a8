// The CPU mip chain equals llvmpipe's glGenerateMipmap texel for texel on the textures it stands
// in for (8-bit linear RGBA, power-of-two sides), so the renders stay byte-identical.
#include <gtest/gtest.h>

#include <random>

#include "meter/engine/gl/texture_mips.hpp"
#include "meter/platform/backend.hpp"

using namespace meter;

namespace {

// Every level glGenerateMipmap makes of `image`, read back through a framebuffer.
std::vector<std::vector<std::uint8_t>> driver_levels(const platform::Gl& gl, const std::vector<std::uint8_t>& image, int w, int h) {
  GLuint tex = 0, fbo = 0;
  gl.GenTextures(1, &tex);
  gl.BindTexture(GL_TEXTURE_2D, tex);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, image.data());
  gl.GenerateMipmap(GL_TEXTURE_2D);
  gl.GenFramebuffers(1, &fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  std::vector<std::vector<std::uint8_t>> levels;
  for (int level = 1; (w >> (level - 1)) > 1 || (h >> (level - 1)) > 1; ++level) {
    const int lw = std::max(1, w >> level), lh = std::max(1, h >> level);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, level);
    std::vector<std::uint8_t> texels(std::size_t(lw) * std::size_t(lh) * 4u);
    gl.ReadPixels(0, 0, lw, lh, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    levels.push_back(std::move(texels));
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.DeleteFramebuffers(1, &fbo);
  gl.DeleteTextures(1, &tex);
  platform::check_gl(gl, "reading glGenerateMipmap's levels");
  return levels;
}

}  // namespace

TEST(TextureMipsRender, TheCpuChainIsLlvmpipesGenerateMipmap) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  std::mt19937 random(44);
  for (const auto& [w, h] : {std::pair{64, 64}, std::pair{128, 16}, std::pair{8, 64}, std::pair{1, 32}}) {
    std::vector<std::uint8_t> image(std::size_t(w) * std::size_t(h) * 4u);
    for (auto& b : image) b = static_cast<std::uint8_t>(random());
    const auto cpu = engine::box_mip_chain(image, w, h);
    const auto gl = driver_levels(backend->gl(), image, w, h);
    ASSERT_EQ(cpu.size(), gl.size()) << w << "x" << h;
    for (std::size_t k = 0; k < cpu.size(); ++k) EXPECT_EQ(cpu[k], gl[k]) << w << "x" << h << " level " << k + 1;
  }
}
