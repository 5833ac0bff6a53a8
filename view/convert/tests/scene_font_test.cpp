// The texts' font travels in the package: the converter finds it (the config's "font", else DejaVu
// Sans from fonts-dejavu-core) and a missing one is a conversion error naming the font and where
// it was looked for; a scene without text needs none; the FONT chunk carries it byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "every_section_scene.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/convert/scene_font.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

// A config with one text binding (or none), optionally naming a font, as if read from `origin`.
SceneConfig text_config(const std::string& origin, const std::string& font = "", bool text = true) {
  std::string json = R"({"format": "meter-scene-config/1")";
  if (!font.empty()) json += R"(, "font": ")" + font + "\"";
  if (text) json += R"(, "bindings": [{"signal": "Vehicle.Speed", "kind": "text", "node": "Text_Speed"}])";
  return meter::config::parse_scene_config(json + "}", origin);
}

std::string error_of(const SceneConfig& config, const FontSearch& search = {}) {
  try {
    load_scene_font(config, search);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

std::vector<std::uint8_t> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(SceneFont, AMissingConfigFontIsAConversionErrorNamingItAndWhereItWasLooked) {
  const std::string dir = engine::test::scratch_dir("scene_font_missing");
  const std::string e = error_of(text_config(dir + "/dial.scene.json", "fonts/Missing.ttf"));
  EXPECT_NE(e.find(dir + "/dial.scene.json: $.font: font file 'fonts/Missing.ttf' not found"), std::string::npos) << e;
  EXPECT_NE(e.find("(looked for " + fs::absolute(dir).string() + "/fonts/Missing.ttf)"), std::string::npos) << e;
  // Through the converter: nothing is written, the font is named.
  const std::string gltf = engine::test::write_dial_scene(dir);
  const std::string json = engine::test::dial_config_json();
  const SceneConfig dial = meter::config::parse_scene_config(
      json.substr(0, json.rfind('}')) + R"(, "font": "Missing.ttf"})", dir + "/dial.scene.json");
  try {
    convert_gltf(gltf, dial, ConvertOptions{.optimize = false});
    FAIL() << "expected a conversion error";
  } catch (const SceneError& err) {
    EXPECT_NE(std::string(err.what()).find("font file 'Missing.ttf' not found"), std::string::npos) << err.what();
  }
}

TEST(SceneFont, AMissingDefaultFontNamesItTheFoldersAndItsPackage) {
  const std::string e = error_of(text_config("cluster.scene.json"), FontSearch{"DejaVuSans.ttf", {"/nonexistent/a", "/nonexistent/b"}});
  EXPECT_NE(e.find("cluster.scene.json: the scene's texts need the font DejaVuSans.ttf"), std::string::npos) << e;
  EXPECT_NE(e.find("looked in /nonexistent/a, /nonexistent/b"), std::string::npos) << e;
  EXPECT_NE(e.find("fonts-dejavu-core"), std::string::npos) << e;
}

TEST(SceneFont, ASceneWithoutTextNeedsNoFont) {
  const SceneFont none = load_scene_font(text_config("plain.scene.json", "Missing.ttf", false), FontSearch{"X.ttf", {}});
  EXPECT_FALSE(none.present());
}

TEST(SceneFont, TheDefaultIsDejaVuSansByteForByteAndAFileThatIsNoFontIsRefused) {
  const SceneFont font = load_scene_font(text_config("cluster.scene.json"));
  EXPECT_EQ(font.name, "DejaVuSans.ttf");
  EXPECT_EQ(font.data, file_bytes(METER_FONT_FILE));
  const std::string dir = engine::test::scratch_dir("scene_font_junk");
  std::ofstream(dir + "/Junk.ttf") << "not a font";
  const std::string e = error_of(text_config(dir + "/s.scene.json", "Junk.ttf"));
  EXPECT_NE(e.find("Junk.ttf': FreeType cannot open it as a font face"), std::string::npos) << e;
}

TEST(SceneFont, TheFontChunkCarriesTheFileByteForByte) {
  Scene s = test::every_section();  // with DejaVu Sans
  const auto bytes = serialize_scene(s);
  const Scene r = engine::deserialize_scene(bytes, "hand.msp");
  EXPECT_EQ(r.font.name, "DejaVuSans.ttf");
  EXPECT_EQ(r.font.data, file_bytes(METER_FONT_FILE));
  EXPECT_EQ(serialize_scene(r), bytes);
  // Bytes FreeType cannot open are refused on load, naming the package and the chunk.
  s.font = {"Junk.ttf", {1, 2, 3}};
  try {
    engine::deserialize_scene(serialize_scene(s), "hand.msp");
    FAIL() << "expected a load error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("hand.msp: chunk FONT (font): font 'Junk.ttf': FreeType cannot open it"),
              std::string::npos) << e.what();
  }
}
