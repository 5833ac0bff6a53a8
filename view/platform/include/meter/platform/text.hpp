// FreeType text for the 2D overlay (digital speed, odometer, gear, temperature, "NO SIGNAL").
//
// The font comes as bytes in memory (the scene package's FONT chunk; FreeType reads it with
// FT_New_Memory_Face): the view opens no font file. A GlyphAtlas rasterises it at one pixel size into a single-channel texture; TextRenderer draws
// UTF-8 strings as textured quads at integer pixel positions with 1:1 texel-to-pixel mapping and
// nearest sampling, so glyphs are exactly as crisp as FreeType rendered them (no scaling).
// Coordinates are target pixels, origin top-left, y down (same as Image rows).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "meter/platform/backend.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::platform {

class TextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Colour as designers write it: sRGB-encoded components 0..1 (like CSS #RRGGBB / 255) and
// straight alpha. The renderer converts to linear when the target encodes sRGB, so "#808080"
// text on an sRGB target stores 128 again (within the driver's sRGB encoder accuracy: llvmpipe's
// is 0.64 of an 8-bit step, so a few values come back 1 off).
struct Color {
  float r = 1.0f, g = 1.0f, b = 1.0f, a = 1.0f;
  // "#RRGGBB" or "#RRGGBBAA"; throws TextError naming the text on anything else.
  static Color from_hex(std::string_view hex);
};

enum class Align { Left, Center, Right };

// A TrueType / OpenType font file's bytes, held by the caller while a GlyphAtlas or TextRenderer is
// being built from them (not after), and a name for messages ("DejaVuSans.ttf in cluster.msp").
struct FontData {
  std::string name;
  std::span<const std::uint8_t> bytes;
};

// Checks that FreeType opens the font as a scalable face with an outline for the digit zero;
// throws TextError naming it otherwise. The converter runs it before embedding a font.
void check_font(const FontData& font);

// Pixel box, origin top-left; empty when width or height is 0.
struct Rect {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  bool contains(int px, int py) const { return px >= x && py >= y && px < x + width && py < y + height; }
};

struct Glyph {
  int atlas_x = 0, atlas_y = 0;  // top-left of the bitmap in the atlas
  int width = 0, height = 0;     // bitmap size
  int bearing_x = 0;             // pen -> left edge of the bitmap
  int bearing_y = 0;             // baseline -> top edge of the bitmap (positive up)
  int advance = 0;               // pen advance in whole pixels
};

// Rasterised glyphs of one face at one pixel size, in one GL_R8 texture.
// Contains printable ASCII, Latin-1 and a few cluster symbols (° – · … µ ±), and the font's
// missing-glyph box, used for any other code point.
class GlyphAtlas {
 public:
  // Throws TextError naming the font (empty, not a font) or the size (must be 4..256).
  GlyphAtlas(const GpuBackend& backend, const FontData& font, int pixel_size);
  ~GlyphAtlas();
  GlyphAtlas(const GlyphAtlas&) = delete;
  GlyphAtlas& operator=(const GlyphAtlas&) = delete;

  // The glyph for a code point, or the missing-glyph box.
  const Glyph& glyph(char32_t code_point) const;
  bool has_glyph(char32_t code_point) const { return glyphs_.contains(code_point); }
  int pixel_size() const { return pixel_size_; }
  int ascender() const { return ascender_; }    // pixels above the baseline
  int descender() const { return descender_; }  // pixels below the baseline (positive)
  int line_height() const { return line_height_; }
  int atlas_width() const { return atlas_width_; }
  int atlas_height() const { return atlas_height_; }
  GLuint texture() const { return texture_; }

 private:
  const Gl* gl_ = nullptr;
  int pixel_size_ = 0;
  int ascender_ = 0, descender_ = 0, line_height_ = 0;
  int atlas_width_ = 0, atlas_height_ = 0;
  GLuint texture_ = 0;
  std::unordered_map<char32_t, Glyph> glyphs_;
  Glyph missing_;
};

// Decodes UTF-8; throws TextError naming the byte offset of the first invalid sequence.
std::u32string decode_utf8(std::string_view text);

class TextRenderer {
 public:
  // Builds the atlas and the renderer's own small program (GLSL ES 3.00).
  TextRenderer(const GpuBackend& backend, const FontData& font, int pixel_size);
  ~TextRenderer();
  TextRenderer(const TextRenderer&) = delete;
  TextRenderer& operator=(const TextRenderer&) = delete;

  // The box of inked pixels draw() would produce for this text anchored at (x, baseline_y):
  // Left puts the pen start at x, Center centres the advance width on x, Right ends it at x.
  // Empty Rect for text without ink (e.g. spaces). Throws TextError on invalid UTF-8.
  Rect measure(std::string_view utf8, int x = 0, int baseline_y = 0, Align align = Align::Left) const;
  // Total pen advance of the text in pixels (layout width, including spaces).
  int advance(std::string_view utf8) const;

  // Draws alpha-blended text into `target` (binds it). State left behind: blending, depth test and
  // face culling disabled, program 0, VAO 0, texture unit 0 bound to the atlas.
  void draw(RenderTarget& target, std::string_view utf8, int x, int baseline_y, Align align,
            Color color);
  // Fills a rectangle (alpha-blended when color.a < 1), e.g. the "NO SIGNAL" banner background.
  void fill_rect(RenderTarget& target, Rect rect, Color color);

  const GlyphAtlas& atlas() const { return *atlas_; }

 private:
  void draw_quads(RenderTarget& target, const std::vector<float>& vertices, Color color, bool textured);

  const Gl* gl_ = nullptr;
  std::unique_ptr<GlyphAtlas> atlas_;
  GLuint program_ = 0;
  GLuint vao_ = 0;
  GLuint vbo_ = 0;
  GLint u_viewport_ = -1, u_color_ = -1, u_textured_ = -1, u_atlas_ = -1;
};

}  // namespace meter::platform
