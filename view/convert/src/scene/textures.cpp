// Textures: every glTF texture decoded to RGBA8 (grey and grey+alpha images expanded), flagged
// sRGB when a material samples it as colour, with the sampler's filters and wraps.
#include "convert_context.hpp"

namespace meter::convert {

namespace {
int gl_filter(int f, int fallback) { return f > 0 ? f : fallback; }
}  // namespace

void validate_textures(ConvertContext& ctx) {
  for (std::size_t i = 0; i < ctx.m.textures.size(); ++i) {
    const auto& t = ctx.m.textures[i];
    if (t.source < 0 || static_cast<std::size_t>(t.source) >= ctx.m.images.size()) {
      ctx.error(idx("textures", i) + ".source", "image index " + std::to_string(t.source) + " out of range");
    } else {
      const auto& im = ctx.m.images[static_cast<std::size_t>(t.source)];
      if (im.image.empty() || im.width <= 0 || im.height <= 0 || im.component < 1 || im.component > 4 || im.bits != 8 ||
          im.image.size() != std::size_t(im.width) * std::size_t(im.height) * std::size_t(im.component)) {
        ctx.error(idx("images", std::size_t(t.source)), "image could not be decoded to 8-bit pixels (PNG/JPEG expected)");
      }
    }
    if (t.sampler >= 0 && static_cast<std::size_t>(t.sampler) >= ctx.m.samplers.size()) {
      ctx.error(idx("textures", i) + ".sampler", "sampler index out of range");
    }
  }
}

void convert_textures(const ConvertContext& ctx, const std::vector<int>& texture_srgb, Scene& s) {
  for (std::size_t i = 0; i < ctx.m.textures.size(); ++i) {
    const auto& t = ctx.m.textures[i];
    const auto& im = ctx.m.images[static_cast<std::size_t>(t.source)];
    Texture out;
    out.name = !t.name.empty() ? t.name : im.name;
    out.width = im.width;
    out.height = im.height;
    out.srgb = texture_srgb[i] == 1;
    out.rgba.resize(std::size_t(im.width) * std::size_t(im.height) * 4);
    for (std::size_t px = 0; px < std::size_t(im.width) * std::size_t(im.height); ++px) {
      const auto* src = im.image.data() + px * std::size_t(im.component);
      std::uint8_t r = src[0], g = im.component >= 3 ? src[1] : src[0], b = im.component >= 3 ? src[2] : src[0];
      std::uint8_t a = im.component == 4 ? src[3] : im.component == 2 ? src[1] : 255;
      out.rgba[px * 4] = r, out.rgba[px * 4 + 1] = g, out.rgba[px * 4 + 2] = b, out.rgba[px * 4 + 3] = a;
    }
    if (t.sampler >= 0) {
      const auto& sm = ctx.m.samplers[static_cast<std::size_t>(t.sampler)];
      out.min_filter = gl_filter(sm.minFilter, out.min_filter);
      out.mag_filter = gl_filter(sm.magFilter, out.mag_filter);
      out.wrap_s = sm.wrapS;
      out.wrap_t = sm.wrapT;
    }
    s.textures.push_back(std::move(out));
  }
}

}  // namespace meter::convert
