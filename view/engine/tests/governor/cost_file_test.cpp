// The meter-costs/1 file: a round trip, every kind of bad file naming its field, and a file that
// does not match the package's draw units rejected by name.
#include "meter/engine/governor/cost_file.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace meter::engine::governor {
namespace {

using bridge::ShadingModel;

const std::string kOrigin = "cluster.meterpkg.costs.json";

CostFile sample() {
  CostFile f;
  f.backend = "egl";
  f.package = "cluster.meterpkg";
  f.overhead = {1.5e-7, 0.42};
  f.globals = {GlobalCost{{4, 1.0f}, 1.0, 0.0, std::nullopt}, GlobalCost{{1, 0.5f}, 0.23, 0.31, 31.25}};
  f.units = {{"needle",
              {LevelCost{ShadingModel::PbrMetallicRoughness, 0, {2.0e-5, 0.11}, std::nullopt},
               LevelCost{ShadingModel::Gouraud, 0, {1.1e-5, -0.02}, 44.5},
               LevelCost{ShadingModel::PbrMetallicRoughness, 1, {1.9e-5, 0.09}, 51.0},
               LevelCost{ShadingModel::Gouraud, 1, {1.0e-5, 0.08}, 40.0}}},
             {"telltale", {LevelCost{ShadingModel::Unlit, 0, {3.0e-6, 0.05}, std::nullopt}}}};
  return f;
}

std::vector<UnitLadder> ladders() {
  UnitLadder needle{"needle", false, {ShadingModel::PbrMetallicRoughness, ShadingModel::Gouraud}, {0.0f, 0.01f}, {1.0f, 0.6f}};
  UnitLadder telltale{"telltale", true, {ShadingModel::Unlit}, {0.0f}, {1.0f}};
  return {needle, telltale};
}

TEST(CostFile, WriteThenParseGivesTheSameFile) {
  const CostFile f = sample();
  const std::string text = write_costs(f);
  EXPECT_NE(text.find("\"format\": \"meter-costs/1\""), std::string::npos);
  EXPECT_EQ(parse_costs(text, kOrigin), f);
  // With the converter's concatenation costs (meter-convert --costs).
  CostFile c = f;
  c.concatenation = ConcatenationCosts{0.0168, 0.0003, 6.2e-05};
  EXPECT_EQ(parse_costs(write_costs(c), kOrigin), c);
}

TEST(CostFile, OptionalKeysMayBeLeftOut) {
  const CostFile f = parse_costs(R"({"format": "meter-costs/1", "overhead": {"a_ms_per_pixel": 0, "b_ms": 0},
      "globals": [{"msaa": 4, "scale": 1, "pixel_factor": 1, "fixed_ms": 0}],
      "units": [{"name": "telltale", "levels": [{"shading": "unlit", "lod": 0, "a_ms_per_pixel": 1e-6, "b_ms": 0.01}]}]})",
                                 kOrigin);
  EXPECT_TRUE(f.backend.empty());
  EXPECT_FALSE(f.globals[0].psnr_db.has_value());
  EXPECT_FALSE(f.units[0].levels[0].psnr_db.has_value());
  EXPECT_FALSE(f.concatenation.has_value());  // a file from before the concatenation costs still reads
  EXPECT_EQ(f.globals[0].level, (GlobalLevel{4, 1.0f}));
}

TEST(CostFile, BindingOrdersUnitsAndLevelsAsTheLadders) {
  CostFile f = sample();
  std::swap(f.units[0], f.units[1]);                    // file order is free
  std::swap(f.units[1].levels[0], f.units[1].levels[3]);
  const CostModel m = bind_costs(f, ladders(), kOrigin);
  ASSERT_EQ(m.units.size(), 2u);
  EXPECT_EQ(m.units[0].name, "needle");
  EXPECT_FALSE(m.units[0].safety);
  EXPECT_TRUE(m.units[1].safety);
  EXPECT_EQ(m.units[0].at({1, 0}).cost.a_ms_per_pixel, 1.1e-5);  // gouraud, lod 0
  EXPECT_EQ(m.units[0].at({0, 1}).cost.a_ms_per_pixel, 1.9e-5);  // pbr, lod 1
  EXPECT_EQ(m.globals.size(), 2u);
}

void expect_stale(const CostFile& f, const std::vector<UnitLadder>& l, const std::vector<std::string>& names) {
  try {
    bind_costs(f, l, kOrigin);
    ADD_FAILURE() << "a stale file was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(kOrigin + ": stale cost file", 0), 0u) << what;
    for (const auto& n : names) EXPECT_NE(what.find(n), std::string::npos) << "no \"" << n << "\" in: " << what;
  }
}

TEST(CostFile, AFileForAnotherConversionIsRejectedNamingWhatDiffers) {
  std::vector<UnitLadder> l = ladders();
  // The package gained a unit and a LOD; the file has a unit and a shading the package lacks.
  l.push_back(UnitLadder{"odometer", false, {ShadingModel::Unlit}, {0.0f}, {1.0f}});
  l[0].lod_errors.push_back(0.04f);
  l[0].lod_triangle_fractions.push_back(0.3f);
  CostFile f = sample();
  f.units.push_back({"gear", {LevelCost{ShadingModel::Unlit, 0, {1e-6, 0.0}, std::nullopt}}});
  f.units[0].levels.push_back(LevelCost{ShadingModel::Flat, 0, {1e-5, 0.0}, 30.0});
  expect_stale(f, l,
               {"missing", "unit 'odometer'", "level 'needle' (pbr, lod 2)", "level 'needle' (gouraud, lod 2)",
                "not in the package", "unit 'gear'", "level 'needle' (flat, lod 0)"});
}

// Each case: one edit of the sample file, and what the error must say (path and expectation).
struct BadCase {
  std::function<void(nlohmann::json&)> edit;
  std::string names;
};

TEST(CostFile, EveryBadFileNamesTheFieldAndWhatWasExpected) {
  using nlohmann::json;
  const json good = json::parse(write_costs(sample()));
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<BadCase> cases = {
      {[](json& j) { j["format"] = "meter-costs/2"; }, "$.format: expected \"meter-costs/1\", got \"meter-costs/2\""},
      {[](json& j) { j.erase("format"); }, "$.format: missing"},
      {[](json& j) { j["overhead"]["b_ms"] = -0.42; }, "$.overhead.b_ms: expected a number >= 0"},
      {[](json& j) { j["overhead"]["a_ms_per_pixel"] = -1e-7; }, "$.overhead.a_ms_per_pixel: expected a number in [0, 1000]"},
      {[&](json& j) { j["overhead"]["a_ms_per_pixel"] = inf; }, "$.overhead.a_ms_per_pixel: expected a number, got null"},
      {[](json& j) { j["overhead"]["a_ms_per_pixel"] = "fast"; }, "$.overhead.a_ms_per_pixel: expected a number, got string"},
      {[](json& j) { j["overhead"].erase("b_ms"); }, "$.overhead.b_ms: missing"},
      {[](json& j) { j["globals"][0]["msaa"] = 0; }, "$.globals[0].msaa: expected an integer sample count in [1, 64]"},
      {[](json& j) { j["globals"][0]["msaa"] = 2.5; }, "$.globals[0].msaa: expected an integer sample count"},
      {[](json& j) { j["globals"][1]["scale"] = 1.5; }, "$.globals[1].scale: expected a number in (0, 1], got 1.5"},
      {[](json& j) { j["globals"][1]["scale"] = 0; }, "$.globals[1].scale: expected a number in (0, 1], got 0"},
      {[](json& j) { j["globals"][1]["scale"] = 1e-50; }, "$.globals[1].scale: expected a number in (0, 1] that a float can hold, got 1e-50"},
      {[](json& j) { j["globals"][1]["pixel_factor"] = 0; }, "$.globals[1].pixel_factor: expected a number in (0, 1000]"},
      {[](json& j) { j["globals"][1]["fixed_ms"] = -1; }, "$.globals[1].fixed_ms: expected a number in [0, 1000000]"},
      {[](json& j) { j["globals"][1]["psnr_db"] = 0; }, "$.globals[1].psnr_db: expected a number in (0, 1000]"},
      {[](json& j) { j["globals"][1]["msaa"] = 4; j["globals"][1]["scale"] = 1.0; },
       "$.globals[1]: duplicate rung (same msaa and scale as globals[0])"},
      {[](json& j) { j["globals"] = json::array(); }, "$.globals: expected at least one rung"},
      {[](json& j) { j["units"][0]["levels"][1]["shading"] = "phong"; },
       "$.units[0].levels[1].shading: expected one of \"unlit\", \"flat\", \"gouraud\", \"blinn-phong\", \"pbr\", got \"phong\""},
      {[](json& j) { j["units"][0]["levels"][1]["lod"] = -1; }, "$.units[0].levels[1].lod: expected an integer LOD index in [0, 1024]"},
      {[](json& j) { j["units"][0]["levels"][3]["lod"] = 0; }, "$.units[0].levels[3]: duplicate level"},
      {[](json& j) { j["units"][0]["levels"][1]["b_ms"] = nullptr; }, "$.units[0].levels[1].b_ms: expected a number, got null"},
      {[](json& j) { j["units"][0]["levels"][1]["psnr_db"] = -3; }, "$.units[0].levels[1].psnr_db: expected a number in (0, 1000]"},
      {[](json& j) { j["units"][0]["levels"] = json::array(); }, "$.units[0].levels: expected at least one level"},
      {[](json& j) { j["units"][1]["name"] = 7; }, "$.units[1].name: expected a string, got number"},
      {[](json& j) { j["units"][1]["colour"] = 1; }, "$.units[1].colour: unknown key (expected one of: levels, name)"},
      {[](json& j) { j["units"] = json::object(); }, "$.units: expected an array, got object"},
      {[](json& j) { j = json::array(); }, "$: expected an object, got array"},
      {[](json& j) { j["concatenation"] = {{"draw_ms", 0.01}, {"vertex_ms", -1e-4}, {"transform_ms", 0}}; },
       "$.concatenation.vertex_ms: expected a number in [0, 1000000]"},
      {[](json& j) { j["concatenation"] = {{"draw_ms", 0.01}, {"vertex_ms", 0}}; }, "$.concatenation.transform_ms: missing"},
  };
  for (const BadCase& c : cases) {
    json doc = good;
    c.edit(doc);
    try {
      parse_costs(doc.dump(2), kOrigin);
      ADD_FAILURE() << "accepted: " << doc.dump();
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(kOrigin + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(c.names), std::string::npos) << "expected \"" << c.names << "\" in: " << what;
    }
  }
  // A number too large for a double: the JSON reader refuses it (it threw its own out_of_range
  // exception through parse_costs before the reader caught every JSON exception).
  std::string huge = good.dump();
  const std::string from = "\"b_ms\":0.42";
  ASSERT_NE(huge.find(from), std::string::npos) << huge;
  huge.replace(huge.find(from), from.size(), "\"b_ms\":1e400");
  try {
    parse_costs(huge, kOrigin);
    ADD_FAILURE() << "1e400 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(kOrigin + ": invalid JSON: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1e400"), std::string::npos) << e.what();
  }
  try {
    parse_costs("{\"format\": ", kOrigin);
    ADD_FAILURE() << "truncated JSON accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(kOrigin + ": invalid JSON"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace meter::engine::governor
