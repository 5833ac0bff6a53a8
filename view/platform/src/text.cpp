#include "meter/platform/text.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace meter::platform {

Color Color::from_hex(std::string_view hex) {
  auto bad = [&] {
    return TextError("colour '" + std::string(hex) + "': expected #RRGGBB or #RRGGBBAA (hex digits)");
  };
  if ((hex.size() != 7 && hex.size() != 9) || hex[0] != '#') throw bad();
  auto nibble = [&](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    throw bad();
  };
  auto byte = [&](std::size_t i) { return float(nibble(hex[i]) * 16 + nibble(hex[i + 1])) / 255.0f; };
  Color c{byte(1), byte(3), byte(5), 1.0f};
  if (hex.size() == 9) c.a = byte(7);
  return c;
}

std::u32string decode_utf8(std::string_view text) {
  std::u32string out;
  out.reserve(text.size());
  std::size_t i = 0;
  auto fail = [&](const char* what) {
    return TextError("invalid UTF-8 at byte " + std::to_string(i) + " of \"" + std::string(text) +
                     "\": " + what);
  };
  while (i < text.size()) {
    const auto b0 = static_cast<unsigned char>(text[i]);
    int extra = 0;
    char32_t cp = 0, min = 0;
    if (b0 < 0x80) { cp = b0; }
    else if ((b0 & 0xE0) == 0xC0) { extra = 1; cp = b0 & 0x1F; min = 0x80; }
    else if ((b0 & 0xF0) == 0xE0) { extra = 2; cp = b0 & 0x0F; min = 0x800; }
    else if ((b0 & 0xF8) == 0xF0) { extra = 3; cp = b0 & 0x07; min = 0x10000; }
    else throw fail("unexpected byte");
    if (i + static_cast<std::size_t>(extra) >= text.size()) throw fail("truncated sequence");
    for (int k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(text[i + static_cast<std::size_t>(k)]);
      if ((b & 0xC0) != 0x80) throw fail("missing continuation byte");
      cp = (cp << 6) | (b & 0x3F);
    }
    if (cp < min) throw fail("overlong encoding");
    if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) throw fail("not a Unicode scalar value");
    out.push_back(cp);
    i += static_cast<std::size_t>(extra) + 1;
  }
  return out;
}

namespace {

// Printable ASCII, Latin-1 (° ± µ · ...) and punctuation/symbols a cluster shows.
std::vector<char32_t> default_charset() {
  std::vector<char32_t> cs;
  for (char32_t c = 0x20; c <= 0x7E; ++c) cs.push_back(c);
  for (char32_t c = 0xA0; c <= 0xFF; ++c) cs.push_back(c);
  for (char32_t c : {0x2013, 0x2014, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2026, 0x2103,
                     0x2190, 0x2191, 0x2192, 0x2193, 0x2212})
    cs.push_back(c);
  return cs;
}

struct FtLibrary {
  FT_Library lib = nullptr;
  FT_Face face = nullptr;
  ~FtLibrary() {
    if (face) FT_Done_Face(face);
    if (lib) FT_Done_FreeType(lib);
  }
};

struct Bitmap {
  Glyph glyph;
  std::vector<std::uint8_t> pixels;
};

Bitmap render_glyph(FT_Face face, FT_UInt index, const std::string& font, char32_t cp) {
  if (FT_Load_Glyph(face, index, FT_LOAD_RENDER) != 0) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(cp));
    throw TextError("font '" + font + "': FreeType cannot render glyph for " + buf);
  }
  const FT_GlyphSlot slot = face->glyph;
  const FT_Bitmap& bm = slot->bitmap;
  Bitmap out;
  out.glyph.width = static_cast<int>(bm.width);
  out.glyph.height = static_cast<int>(bm.rows);
  out.glyph.bearing_x = slot->bitmap_left;
  out.glyph.bearing_y = slot->bitmap_top;
  out.glyph.advance = static_cast<int>((slot->advance.x + 32) >> 6);
  if (bm.pixel_mode != FT_PIXEL_MODE_GRAY && bm.width > 0) {
    throw TextError("font '" + font + "': glyph bitmap is not 8-bit grey (bitmap-only font?)");
  }
  out.pixels.resize(static_cast<std::size_t>(bm.width) * bm.rows);
  for (unsigned y = 0; y < bm.rows; ++y) {
    for (unsigned x = 0; x < bm.width; ++x) {
      out.pixels[static_cast<std::size_t>(y) * bm.width + x] =
          bm.buffer[static_cast<std::ptrdiff_t>(y) * bm.pitch + x];
    }
  }
  return out;
}

// The face of an in-memory font file at one pixel size; `font.bytes` must outlive it.
void open_face(FtLibrary& ft, const FontData& font, int pixel_size) {
  const std::string& name = font.name;
  if (font.bytes.empty()) throw TextError("font '" + name + "': no font data (an empty font file)");
  if (FT_Init_FreeType(&ft.lib) != 0) throw TextError("FreeType initialisation failed");
  if (FT_New_Memory_Face(ft.lib, font.bytes.data(), static_cast<FT_Long>(font.bytes.size()), 0, &ft.face) != 0) {
    throw TextError("font '" + name + "': FreeType cannot open it as a font face (not a TTF/OTF?)");
  }
  if (FT_Set_Pixel_Sizes(ft.face, 0, static_cast<FT_UInt>(pixel_size)) != 0) {
    throw TextError("font '" + name + "': cannot set pixel size " + std::to_string(pixel_size));
  }
}

}  // namespace

void check_font(const FontData& font) {
  FtLibrary ft;
  open_face(ft, font, 24);
  if (!FT_IS_SCALABLE(ft.face)) throw TextError("font '" + font.name + "': not a scalable (outline) font");
  if (FT_Get_Char_Index(ft.face, U'0') == 0) throw TextError("font '" + font.name + "': has no glyph for the digit 0");
}

GlyphAtlas::GlyphAtlas(const GpuBackend& backend, const FontData& font_data, int pixel_size)
    : gl_(&backend.gl()), pixel_size_(pixel_size) {
  const std::string& font = font_data.name;
  if (pixel_size < 4 || pixel_size > 256) {
    throw TextError("font '" + font + "': pixel size " + std::to_string(pixel_size) +
                    " outside 4..256");
  }
  FtLibrary ft;
  open_face(ft, font_data, pixel_size);
  ascender_ = static_cast<int>((ft.face->size->metrics.ascender + 32) >> 6);
  descender_ = static_cast<int>((-ft.face->size->metrics.descender + 32) >> 6);
  line_height_ = static_cast<int>((ft.face->size->metrics.height + 32) >> 6);

  std::vector<std::pair<char32_t, Bitmap>> bitmaps;
  Bitmap missing = render_glyph(ft.face, 0, font, 0);
  for (char32_t cp : default_charset()) {
    const FT_UInt index = FT_Get_Char_Index(ft.face, cp);
    if (index == 0) continue;  // the face lacks it: the missing-glyph box is drawn instead
    bitmaps.emplace_back(cp, render_glyph(ft.face, index, font, cp));
  }

  // Shelf packing with one empty texel between glyphs so nearest sampling never bleeds.
  atlas_width_ = pixel_size <= 48 ? 512 : 1024;
  int pen_x = 1, pen_y = 1, shelf = 0;
  auto place = [&](Glyph& g) {
    if (g.width > atlas_width_ - 2) {
      throw TextError("font '" + font + "': glyph wider than the atlas at size " + std::to_string(pixel_size));
    }
    if (pen_x + g.width + 1 > atlas_width_) {
      pen_x = 1;
      pen_y += shelf + 1;
      shelf = 0;
    }
    g.atlas_x = pen_x;
    g.atlas_y = pen_y;
    pen_x += g.width + 1;
    shelf = std::max(shelf, g.height);
  };
  place(missing.glyph);
  for (auto& [cp, bm] : bitmaps) place(bm.glyph);
  atlas_height_ = pen_y + shelf + 1;
  if (atlas_height_ > gl_->info.max_texture_size) {
    throw TextError("font '" + font + "': glyph atlas at pixel size " + std::to_string(pixel_size) +
                    " needs " + std::to_string(atlas_width_) + "x" + std::to_string(atlas_height_) +
                    " texels, above GL_MAX_TEXTURE_SIZE " + std::to_string(gl_->info.max_texture_size));
  }

  std::vector<std::uint8_t> texels(static_cast<std::size_t>(atlas_width_) * atlas_height_, 0);
  auto blit = [&](const Bitmap& bm) {
    for (int y = 0; y < bm.glyph.height; ++y)
      std::copy_n(bm.pixels.begin() + static_cast<std::ptrdiff_t>(y) * bm.glyph.width, bm.glyph.width,
                  texels.begin() + static_cast<std::ptrdiff_t>(bm.glyph.atlas_y + y) * atlas_width_ +
                      bm.glyph.atlas_x);
  };
  blit(missing);
  missing_ = missing.glyph;
  for (auto& [cp, bm] : bitmaps) {
    blit(bm);
    glyphs_.emplace(cp, bm.glyph);
  }

  const Gl& gl = *gl_;
  gl.GenTextures(1, &texture_);
  gl.BindTexture(GL_TEXTURE_2D, texture_);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, atlas_width_, atlas_height_, 0, GL_RED, GL_UNSIGNED_BYTE,
                texels.data());
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.BindTexture(GL_TEXTURE_2D, 0);
  try {
    check_gl(gl, "GlyphAtlas '" + font + "' upload");
  } catch (...) {
    gl.DeleteTextures(1, &texture_);
    throw;
  }
}

GlyphAtlas::~GlyphAtlas() {
  if (texture_) gl_->DeleteTextures(1, &texture_);
}

const Glyph& GlyphAtlas::glyph(char32_t code_point) const {
  auto it = glyphs_.find(code_point);
  return it == glyphs_.end() ? missing_ : it->second;
}

namespace {

// Pixel-space quads; texelFetch at the fragment's texel makes the 1:1 mapping exact (no filtering,
// no rounding of normalised coordinates).
constexpr const char* kVertexShader = R"(#version 300 es
layout(location = 0) in vec2 a_pos;   // target pixels, origin top-left
layout(location = 1) in vec2 a_uv;    // atlas texels
uniform vec2 u_viewport;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = vec4(a_pos.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_pos.y / u_viewport.y * 2.0, 0.0, 1.0);
}
)";

constexpr const char* kFragmentShader = R"(#version 300 es
precision highp float;
in vec2 v_uv;
uniform sampler2D u_atlas;
uniform vec4 u_color;       // linear RGB (or raw for non-sRGB targets), straight alpha
uniform bool u_textured;
out vec4 o_color;
void main() {
  float coverage = u_textured ? texelFetch(u_atlas, ivec2(floor(v_uv)), 0).r : 1.0;
  o_color = vec4(u_color.rgb, u_color.a * coverage);
}
)";

}  // namespace

TextRenderer::TextRenderer(const GpuBackend& backend, const FontData& font, int pixel_size)
    : gl_(&backend.gl()), atlas_(std::make_unique<GlyphAtlas>(backend, font, pixel_size)) {
  const Gl& gl = *gl_;
  program_ = compile_program(gl, kVertexShader, kFragmentShader, "TextRenderer");
  u_viewport_ = gl.GetUniformLocation(program_, "u_viewport");
  u_color_ = gl.GetUniformLocation(program_, "u_color");
  u_textured_ = gl.GetUniformLocation(program_, "u_textured");
  u_atlas_ = gl.GetUniformLocation(program_, "u_atlas");
  gl.GenVertexArrays(1, &vao_);
  gl.GenBuffers(1, &vbo_);
  gl.BindVertexArray(vao_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  gl.EnableVertexAttribArray(1);
  gl.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                         reinterpret_cast<const void*>(2 * sizeof(float)));
  gl.BindVertexArray(0);
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);
  check_gl(gl, "TextRenderer setup");
}

TextRenderer::~TextRenderer() {
  const Gl& gl = *gl_;
  if (vbo_) gl.DeleteBuffers(1, &vbo_);
  if (vao_) gl.DeleteVertexArrays(1, &vao_);
  if (program_) gl.DeleteProgram(program_);
}

namespace {

std::u32string checked_text(std::string_view utf8) {
  std::u32string text = decode_utf8(utf8);
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] < 0x20 || text[i] == 0x7F) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(text[i]));
      throw TextError("text \"" + std::string(utf8) + "\": control character " + buf +
                      " at character " + std::to_string(i) + " (single-line text only)");
    }
  }
  return text;
}

int text_advance(const GlyphAtlas& atlas, const std::u32string& text) {
  int adv = 0;
  for (char32_t cp : text) adv += atlas.glyph(cp).advance;
  return adv;
}

int pen_start(int x, int advance, Align align) {
  switch (align) {
    case Align::Left: return x;
    case Align::Center: return x - advance / 2;
    case Align::Right: return x - advance;
  }
  return x;
}

}  // namespace

int TextRenderer::advance(std::string_view utf8) const { return text_advance(*atlas_, checked_text(utf8)); }

Rect TextRenderer::measure(std::string_view utf8, int x, int baseline_y, Align align) const {
  const std::u32string text = checked_text(utf8);
  int pen = pen_start(x, text_advance(*atlas_, text), align);
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool any = false;
  for (char32_t cp : text) {
    const Glyph& g = atlas_->glyph(cp);
    if (g.width > 0 && g.height > 0) {
      const int gx0 = pen + g.bearing_x, gy0 = baseline_y - g.bearing_y;
      const int gx1 = gx0 + g.width, gy1 = gy0 + g.height;
      if (!any) {
        x0 = gx0; y0 = gy0; x1 = gx1; y1 = gy1;
        any = true;
      } else {
        x0 = std::min(x0, gx0); y0 = std::min(y0, gy0);
        x1 = std::max(x1, gx1); y1 = std::max(y1, gy1);
      }
    }
    pen += g.advance;
  }
  if (!any) return Rect{pen_start(x, 0, align), baseline_y, 0, 0};
  return Rect{x0, y0, x1 - x0, y1 - y0};
}

void TextRenderer::draw(RenderTarget& target, std::string_view utf8, int x, int baseline_y,
                        Align align, Color color) {
  const std::u32string text = checked_text(utf8);
  int pen = pen_start(x, text_advance(*atlas_, text), align);
  std::vector<float> v;
  v.reserve(text.size() * 24);
  for (char32_t cp : text) {
    const Glyph& g = atlas_->glyph(cp);
    if (g.width > 0 && g.height > 0) {
      const float px0 = float(pen + g.bearing_x), py0 = float(baseline_y - g.bearing_y);
      const float px1 = px0 + float(g.width), py1 = py0 + float(g.height);
      const float u0 = float(g.atlas_x), t0 = float(g.atlas_y);
      const float u1 = u0 + float(g.width), t1 = t0 + float(g.height);
      const float quad[24] = {px0, py0, u0, t0, px1, py0, u1, t0, px1, py1, u1, t1,
                              px0, py0, u0, t0, px1, py1, u1, t1, px0, py1, u0, t1};
      v.insert(v.end(), quad, quad + 24);
    }
    pen += g.advance;
  }
  if (!v.empty()) draw_quads(target, v, color, true);
}

void TextRenderer::fill_rect(RenderTarget& target, Rect r, Color color) {
  if (r.empty()) return;
  const float x0 = float(r.x), y0 = float(r.y), x1 = float(r.x + r.width), y1 = float(r.y + r.height);
  const std::vector<float> v = {x0, y0, 0, 0, x1, y0, 0, 0, x1, y1, 0, 0,
                                x0, y0, 0, 0, x1, y1, 0, 0, x0, y1, 0, 0};
  draw_quads(target, v, color, false);
}

void TextRenderer::draw_quads(RenderTarget& target, const std::vector<float>& vertices, Color color,
                              bool textured) {
  const Gl& gl = *gl_;
  target.bind();
  // Designers give sRGB colours; an sRGB target expects linear shader output.
  auto channel = [&](float c) {
    return target.srgb() ? static_cast<float>(srgb_to_linear(std::clamp(c, 0.0f, 1.0f))) : c;
  };
  gl.UseProgram(program_);
  gl.Uniform2f(u_viewport_, float(target.width()), float(target.height()));
  gl.Uniform4f(u_color_, channel(color.r), channel(color.g), channel(color.b), std::clamp(color.a, 0.0f, 1.0f));
  gl.Uniform1i(u_textured_, textured ? 1 : 0);
  gl.Uniform1i(u_atlas_, 0);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, atlas_->texture());
  gl.Disable(GL_DEPTH_TEST);
  gl.Disable(GL_CULL_FACE);
  gl.Enable(GL_BLEND);
  // Straight-alpha "over" for colour; alpha accumulates coverage.
  gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl.BlendEquation(GL_FUNC_ADD);
  gl.BindVertexArray(vao_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                vertices.data(), GL_STREAM_DRAW);
  gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / 4));
  gl.BindVertexArray(0);
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);
  gl.Disable(GL_BLEND);
  gl.UseProgram(0);
  check_gl(gl, "TextRenderer draw");
}

}  // namespace meter::platform
