// The record dump (meter/engine/package_dump.hpp): every stored field of every record as one exact
// line, long arrays as their size and hash; and the package round trip it guards: a scene written
// and read back dumps exactly as the scene itself.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "every_section_scene.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_dump.hpp"
#include "meter/engine/package_reader.hpp"

using namespace meter;
using namespace meter::convert;

namespace {
bool has_line(const std::string& dump, const std::string& line) {
  return dump.find("\n" + line + "\n") != std::string::npos || dump.rfind(line + "\n", 0) == 0;
}
}  // namespace

TEST(PackageDump, PrintsEveryFieldExactly) {
  const std::string d = engine::dump_scene(meter::convert::test::every_section());
  for (const char* line : {
           "source_name = \"hand-built\"",
           "nodes.count = 2",
           "nodes[0].translation = (1, 2, 3)",
           "nodes[0].rotation = (0.5, 0.5, 0.5, 0.5)",
           "nodes[1].weights = [0.25]",
           "materials[0].base_color = (0.100000001, 0.200000003, 0.300000012, 0.400000006)",
           "materials[0].texture = [0, -1, -1, -1, -1, -1]",
           "materials[0].uv_transform[0] = (2, 0, 0, 0, 2, 0, 0, 0, 2)",
           "textures[0].rgba = [255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 0]",
           "lights[0].cast_shadow = true",
           "programs[0].program.features.lights.spot = 1",
           "programs[0].program.features.lights.shadows = 1",
           "programs[0].program.samplers[0].index = 0",
           "programs[0].optimize_report.spirv_instructions_before = 120",
           "programs[0].optimize_report.folded[0] = \"u_base_color\"",
           "meshes[0].primitives[0].lods[0].triangle_fraction = 0.5",
           "draw_levels[0].shadings[0].base_scale = 0.25",
           "environment.strength = 0.5",
       }) {
    EXPECT_TRUE(has_line(d, line)) << "missing: " << line << "\n" << d;
  }
  // Texts with quotes or longer than a line, and arrays over 16 values: size and FNV-1a 64.
  EXPECT_NE(d.find("environment.probe.rgb = 1152 values, fnv1a64 "), std::string::npos) << d;
  EXPECT_TRUE(has_line(d, "font.name = \"DejaVuSans.ttf\"")) << d;
  const std::string font_size = std::to_string(std::filesystem::file_size(METER_FONT_FILE));
  EXPECT_NE(d.find("font.data = " + font_size + " values, fnv1a64 "), std::string::npos) << d;
}

TEST(PackageDump, LongTextsAndQuotesAreHashed) {
  Scene s;
  s.config.source_json = R"({"format": "meter-scene-config/1"})";
  const std::string d = engine::dump_scene(s);
  EXPECT_NE(d.find("config = 34 bytes, fnv1a64 "), std::string::npos) << d;
}

// The cheap guard of the package round trip: write -> read -> dump equals the scene's own dump.
TEST(PackageDump, WrittenAndReadBackDumpsTheSame) {
  const Scene s = meter::convert::test::every_section();
  EXPECT_EQ(engine::dump_scene(engine::deserialize_scene(serialize_scene(s), "hand.msp")), engine::dump_scene(s));
}
