// FreeType text: UTF-8 decoding, colours, font errors, and on both backends: glyph pixels equal
// FreeType's own bitmap (1:1, crisp), all ink inside the measured box, alignment, filled rects.
#include <gtest/gtest.h>

#include <ft2build.h>
#include FT_FREETYPE_H

#include <fstream>
#include <iterator>
#include <vector>

#include "gl_test_util.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/text.hpp"

namespace mp = meter::platform;
using mp::BackendKind;

TEST(Utf8, DecodesValidText) {
  EXPECT_EQ(mp::decode_utf8("km/h"), U"km/h");
  EXPECT_EQ(mp::decode_utf8("21\xC2\xB0" "C"), U"21\u00B0C");              // °
  EXPECT_EQ(mp::decode_utf8("\xE2\x80\x93"), U"\u2013");                    // –
  EXPECT_EQ(mp::decode_utf8("\xF0\x9F\x9A\x97"), U"\U0001F697");           // 4-byte
  EXPECT_EQ(mp::decode_utf8(""), U"");
}

TEST(Utf8, RejectsInvalidSequencesWithTheOffset) {
  auto message = [](std::string_view s) {
    try {
      mp::decode_utf8(s);
    } catch (const mp::TextError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("ab\xC2").find("byte 2"), std::string::npos) << message("ab\xC2");  // truncated
  EXPECT_NE(message("a\x80").find("byte 1"), std::string::npos);                      // stray continuation
  EXPECT_NE(message("\xC0\xAF").find("overlong"), std::string::npos);
  EXPECT_NE(message("\xED\xA0\x80").find("scalar"), std::string::npos);               // surrogate
  EXPECT_NE(message("\xF4\x90\x80\x80").find("scalar"), std::string::npos);           // > U+10FFFF
  EXPECT_NE(message("\xE2\x28\xA1").find("continuation"), std::string::npos);
}

TEST(Color, ParsesHex) {
  const mp::Color c = mp::Color::from_hex("#FF8000");
  EXPECT_FLOAT_EQ(c.r, 1.0f);
  EXPECT_FLOAT_EQ(c.g, 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(c.b, 0.0f);
  EXPECT_FLOAT_EQ(c.a, 1.0f);
  EXPECT_FLOAT_EQ(mp::Color::from_hex("#00000080").a, 128.0f / 255.0f);
  EXPECT_THROW(mp::Color::from_hex("FF8000"), mp::TextError);
  EXPECT_THROW(mp::Color::from_hex("#FF80"), mp::TextError);
  EXPECT_THROW(mp::Color::from_hex("#GG8000"), mp::TextError);
}

// DejaVu Sans (fonts-dejavu-core, found by the build) read once into memory, as the scene package
// carries it.
const mp::FontData& dejavu() {
  static const std::vector<std::uint8_t> bytes = [] {
    std::ifstream in(METER_FONT_FILE, std::ios::binary);
    return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }();
  static const mp::FontData font{"DejaVuSans.ttf", bytes};
  return font;
}

class TextTest : public ::testing::TestWithParam<BackendKind> {
 protected:
  void SetUp() override { backend_ = mp::create_backend(GetParam()); }
  std::unique_ptr<mp::GpuBackend> backend_;
};

INSTANTIATE_TEST_SUITE_P(Both, TextTest, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

TEST_P(TextTest, FontErrorsNameTheFont) {
  // The font comes from memory (the scene package): empty bytes and bytes that are no font are
  // refused naming it, as is a size outside 4..256.
  try {
    mp::TextRenderer r(*backend_, mp::FontData{"Empty.ttf", {}}, 20);
    FAIL() << "expected TextError";
  } catch (const mp::TextError& e) {
    EXPECT_NE(std::string(e.what()).find("Empty.ttf"), std::string::npos) << e.what();
  }
  const std::string junk = "definitely not a TrueType font";
  const mp::FontData not_font{"not-a-font.ttf", {reinterpret_cast<const std::uint8_t*>(junk.data()), junk.size()}};
  try {
    mp::TextRenderer r(*backend_, not_font, 20);
    FAIL() << "expected TextError";
  } catch (const mp::TextError& e) {
    EXPECT_NE(std::string(e.what()).find("not-a-font.ttf"), std::string::npos) << e.what();
  }
  EXPECT_THROW(mp::check_font(not_font), mp::TextError);
  EXPECT_NO_THROW(mp::check_font(dejavu()));
  EXPECT_THROW(mp::TextRenderer(*backend_, dejavu(), 2), mp::TextError);
}

TEST_P(TextTest, GlyphPixelsEqualFreeTypeBitmapOneToOne) {
  constexpr int kSize = 32;
  mp::TextRenderer text(*backend_, dejavu(), kSize);
  // Non-sRGB target: white over black then stores coverage itself, so the comparison is exact.
  mp::RenderTarget target(*backend_, {.width = 64, .height = 48, .samples = 1, .srgb = false});
  backend_->gl().ClearColor(0, 0, 0, 1);
  backend_->gl().Clear(GL_COLOR_BUFFER_BIT);
  text.draw(target, "g", 10, 30, mp::Align::Left, {1, 1, 1, 1});
  const mp::Image img = target.resolve_and_read();

  // FreeType directly, independent of the atlas code.
  FT_Library lib = nullptr;
  FT_Face face = nullptr;
  ASSERT_EQ(FT_Init_FreeType(&lib), 0);
  ASSERT_EQ(FT_New_Face(lib, METER_FONT_FILE, 0, &face), 0);
  ASSERT_EQ(FT_Set_Pixel_Sizes(face, 0, kSize), 0);
  ASSERT_EQ(FT_Load_Char(face, 'g', FT_LOAD_RENDER), 0);
  const FT_Bitmap& bm = face->glyph->bitmap;
  const int left = 10 + face->glyph->bitmap_left, top = 30 - face->glyph->bitmap_top;
  int mismatches = 0, ink = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      int expected = 0;
      if (x >= left && y >= top && x < left + int(bm.width) && y < top + int(bm.rows))
        expected = bm.buffer[(y - top) * bm.pitch + (x - left)];
      const int got = img.pixel(x, y)[0];
      ink += got > 0;
      mismatches += got != expected;
    }
  FT_Done_Face(face);
  FT_Done_FreeType(lib);
  EXPECT_GT(ink, 40);
  EXPECT_EQ(mismatches, 0);
}

TEST_P(TextTest, InkStaysInsideTheMeasuredBox) {
  mp::TextRenderer text(*backend_, dejavu(), 28);
  const int w = 400, h = 160;
  struct Case {
    const char* s;
    int x, y;
    mp::Align align;
  };
  const Case cases[] = {{"123 km/h", 20, 50, mp::Align::Left},
                        {"Trip 1234.5 km \xE2\x80\x93 21\xC2\xB0" "C", 200, 100, mp::Align::Center},
                        {"gear: D", 390, 140, mp::Align::Right}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.s);
    mp::RenderTarget target(*backend_, {.width = w, .height = h, .samples = 4});
    backend_->gl().ClearColor(0, 0, 0, 1);
    backend_->gl().Clear(GL_COLOR_BUFFER_BIT);
    text.draw(target, c.s, c.x, c.y, c.align, mp::Color::from_hex("#E0F0FF"));
    const mp::Image img = target.resolve_and_read();
    const mp::Rect box = text.measure(c.s, c.x, c.y, c.align);
    ASSERT_FALSE(box.empty());
    int inside = 0, outside = 0;
    int ix0 = w, iy0 = h, ix1 = -1, iy1 = -1;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::uint8_t* p = img.pixel(x, y);
        if (p[0] == 0 && p[1] == 0 && p[2] == 0) continue;
        (box.contains(x, y) ? inside : outside)++;
        ix0 = std::min(ix0, x); iy0 = std::min(iy0, y);
        ix1 = std::max(ix1, x); iy1 = std::max(iy1, y);
      }
    EXPECT_EQ(outside, 0);
    EXPECT_GT(inside, 100);
    // The box is tight: FreeType's bitmap boxes can carry at most one blank edge row/column.
    EXPECT_LE(ix0 - box.x, 1);
    EXPECT_LE(iy0 - box.y, 1);
    EXPECT_LE(box.x + box.width - 1 - ix1, 1);
    EXPECT_LE(box.y + box.height - 1 - iy1, 1);
  }
}

TEST_P(TextTest, AlignmentShiftsByTheAdvance) {
  mp::TextRenderer text(*backend_, dejavu(), 24);
  const int adv = text.advance("88.8");
  EXPECT_GT(adv, 30);
  const mp::Rect left = text.measure("88.8", 100, 50, mp::Align::Left);
  EXPECT_EQ(text.measure("88.8", 100, 50, mp::Align::Right).x, left.x - adv);
  EXPECT_EQ(text.measure("88.8", 100, 50, mp::Align::Center).x, left.x - adv / 2);
  EXPECT_TRUE(text.measure("   ").empty());
  EXPECT_GT(text.advance("   "), 0);
  EXPECT_THROW(text.measure("two\nlines"), mp::TextError);
}

TEST_P(TextTest, MissingCodePointsDrawTheMissingGlyphBox) {
  mp::TextRenderer text(*backend_, dejavu(), 20);
  EXPECT_FALSE(text.atlas().has_glyph(U'\U0001F697'));
  EXPECT_FALSE(text.measure("\xF0\x9F\x9A\x97").empty());  // .notdef box has ink
  EXPECT_TRUE(text.atlas().has_glyph(U'\u00B0'));
}

TEST_P(TextTest, FillRectCoversExactlyTheRect) {
  mp::TextRenderer text(*backend_, dejavu(), 16);
  mp::RenderTarget target(*backend_, {.width = 48, .height = 24, .samples = 4});
  backend_->gl().ClearColor(0, 0, 0, 1);
  backend_->gl().Clear(GL_COLOR_BUFFER_BIT);
  text.fill_rect(target, {10, 5, 20, 8}, mp::Color::from_hex("#C01010"));
  const mp::Image img = target.resolve_and_read();
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool in = x >= 10 && x < 30 && y >= 5 && y < 13;
      const std::uint8_t* p = img.pixel(x, y);
      ASSERT_EQ(p[0], in ? 0xC0 : 0) << x << "," << y;  // sRGB colour in, same sRGB byte out
      ASSERT_EQ(p[1], in ? 0x10 : 0) << x << "," << y;
    }
}
