// The reload logic without a window: conversion of the artist's files, the last good scene kept
// over bad saves with the converter's message, and the settle time that folds one save's events.
#include "meter/preview/scene_reloader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "preview_files.hpp"

namespace meter::preview {
namespace {

using testing::scratch_dir;
using testing::save_by_rename;
using ::testing::HasSubstr;
namespace fs = std::filesystem;
using Clock = SceneReloader::Clock;
using std::chrono::milliseconds;

const fs::path kGauge = fs::path(METER_SOURCE_DIR) / "scenes" / "minimal-gauge";

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The minimal gauge copied into a fresh folder: the artist's working copy.
SceneFiles gauge_copy(const fs::path& dir) {
  fs::copy_file(kGauge / "minimal-gauge.glb", dir / "gauge.glb");
  fs::copy_file(kGauge / "minimal-gauge.scene.json", dir / "gauge.scene.json");
  return {(dir / "gauge.glb").string(), (dir / "gauge.scene.json").string()};
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(SceneReloader, ConvertsTheArtistsFiles) {
  const auto files = gauge_copy(scratch_dir());
  SceneReloader r(files);
  EXPECT_EQ(r.generation(), 0u);
  EXPECT_EQ(r.scene(), nullptr);
  ASSERT_TRUE(r.reload()) << r.error();
  EXPECT_EQ(r.generation(), 1u);
  ASSERT_NE(r.scene(), nullptr);
  EXPECT_EQ(r.scene()->config.size, (std::array<int, 2>{640, 480}));
  ASSERT_EQ(r.scene()->config.bindings.size(), 1u);
  EXPECT_EQ(r.scene()->config.bindings[0].signal, "Vehicle.Speed");
  EXPECT_FALSE(r.scene()->draws.empty());
  EXPECT_FALSE(r.scene()->programs.empty());
  EXPECT_TRUE(r.error().empty());
  EXPECT_GT(r.last_convert_ms(), 0.0);
}

TEST(SceneReloader, AConfigSaveReusesTheOptimizedProgramsAndDrawsTheSame) {
  const auto files = gauge_copy(scratch_dir());
  SceneReloader r(files);
  ASSERT_TRUE(r.reload()) << r.error();
  const std::size_t programs = r.programs().size();
  EXPECT_GT(programs, 0u);
  EXPECT_EQ(r.programs().hits(), 0u);
  // A colour of the config that no program folds: every program comes from the cache.
  save_by_rename(files.config, replaced(read_text(files.config), "\"clear_color\": [0.0, 0.0, 0.0, 1.0]",
                                        "\"clear_color\": [0.0, 0.2, 0.5, 1.0]"));
  ASSERT_TRUE(r.reload()) << r.error();
  EXPECT_EQ(r.programs().hits(), programs);
  EXPECT_EQ(r.programs().size(), programs);
  // ... and they are the programs a conversion without the cache makes.
  const auto fresh = convert_scene(files, *protocol::active_catalog());
  ASSERT_EQ(r.scene()->programs.size(), fresh->programs.size());
  for (std::size_t i = 0; i < fresh->programs.size(); ++i) {
    EXPECT_EQ(r.scene()->programs[i].program.vertex_source, fresh->programs[i].program.vertex_source) << i;
    EXPECT_EQ(r.scene()->programs[i].program.fragment_source, fresh->programs[i].program.fragment_source) << i;
    EXPECT_EQ(shadergen::describe(r.scene()->programs[i].program), shadergen::describe(fresh->programs[i].program)) << i;
  }
}

TEST(SceneReloader, ABadSaveKeepsTheLastGoodSceneAndGivesTheConvertersMessage) {
  const auto files = gauge_copy(scratch_dir());
  const std::string good = read_text(files.config);
  SceneReloader r(files);
  ASSERT_TRUE(r.reload()) << r.error();
  const auto first = r.scene();

  // A binding naming an animation the export does not have.
  save_by_rename(files.config, replaced(good, "\"SpeedNeedle\"", "\"SpeedNeedel\""));
  EXPECT_FALSE(r.reload());
  EXPECT_THAT(r.error(), HasSubstr("SpeedNeedel"));
  EXPECT_EQ(r.scene(), first) << "the last good scene stays";
  EXPECT_EQ(r.generation(), 1u);

  // Half a JSON file (a save caught mid-write): the parser's message names the config file.
  save_by_rename(files.config, good.substr(0, good.size() / 2));
  EXPECT_FALSE(r.reload());
  EXPECT_THAT(r.error(), HasSubstr("gauge.scene.json"));
  EXPECT_EQ(r.scene(), first);

  // A truncated export.
  const std::string glb = read_text(files.gltf);
  save_by_rename(files.config, good);
  save_by_rename(files.gltf, glb.substr(0, 100));
  EXPECT_FALSE(r.reload());
  EXPECT_THAT(r.error(), HasSubstr("gauge.glb"));
  EXPECT_EQ(r.scene(), first);

  // Fixed: the new scene replaces it, with the edit.
  save_by_rename(files.gltf, glb);
  save_by_rename(files.config, replaced(good, "\"clear_color\": [0.0, 0.0, 0.0, 1.0]", "\"clear_color\": [0.0, 0.2, 0.5, 1.0]"));
  ASSERT_TRUE(r.reload()) << r.error();
  EXPECT_EQ(r.generation(), 2u);
  EXPECT_NE(r.scene(), first);
  EXPECT_EQ(r.scene()->config.clear_color, (std::array<double, 4>{0.0, 0.2, 0.5, 1.0}));
  EXPECT_TRUE(r.error().empty());
  EXPECT_EQ(first->config.clear_color, (std::array<double, 4>{0.0, 0.0, 0.0, 1.0})) << "the old scene is untouched";
}

// Waits for the worker's conversion, as the preview loop does between window frames.
bool finished(SceneReloader& r) {
  for (;;) {
    if (const auto done = r.finish()) return *done;
    EXPECT_TRUE(r.converting());
    std::this_thread::sleep_for(milliseconds(5));
  }
}

TEST(SceneReloader, ConvertsOnAWorkerWhileTheLastSceneStays) {
  const auto files = gauge_copy(scratch_dir());
  const std::string good = read_text(files.config);
  SceneReloader r(files);
  ASSERT_TRUE(r.reload()) << r.error();
  const auto first = r.scene();
  save_by_rename(files.config, replaced(good, "\"clear_color\": [0.0, 0.0, 0.0, 1.0]", "\"clear_color\": [1.0, 0.0, 0.0, 1.0]"));
  const auto t0 = Clock::now();
  r.changed(t0);
  r.begin();
  EXPECT_TRUE(r.converting());
  EXPECT_FALSE(r.pending());
  EXPECT_EQ(r.converting_change(), t0);
  // A save while it converts: pending again, converted after this one.
  r.changed(t0 + milliseconds(5));
  EXPECT_TRUE(r.pending());
  EXPECT_EQ(r.scene(), first) << "the scene changes only when the conversion is taken";
  ASSERT_TRUE(finished(r)) << r.error();
  EXPECT_FALSE(r.converting());
  EXPECT_FALSE(r.finish().has_value()) << "a result is taken once";
  EXPECT_EQ(r.generation(), 2u);
  EXPECT_EQ(r.scene()->config.clear_color, (std::array<double, 4>{1.0, 0.0, 0.0, 1.0}));
  EXPECT_TRUE(r.pending());
  EXPECT_EQ(r.first_change(), t0 + milliseconds(5));
  // A bad save converted on the worker: the message, and the last good scene stays.
  save_by_rename(files.config, "{");
  r.begin();
  EXPECT_FALSE(finished(r));
  EXPECT_THAT(r.error(), HasSubstr("gauge.scene.json"));
  EXPECT_EQ(r.generation(), 2u);
  EXPECT_EQ(r.scene()->config.clear_color, (std::array<double, 4>{1.0, 0.0, 0.0, 1.0}));
}

TEST(SceneReloader, AReloadWaitsUntilTheSaveSettled) {
  SceneReloader r({"unused.glb", "unused.json"}, milliseconds(40));
  const auto t0 = Clock::now();
  EXPECT_FALSE(r.due(t0 + milliseconds(1000))) << "nothing changed";
  r.changed(t0);
  EXPECT_FALSE(r.due(t0 + milliseconds(39)));
  EXPECT_TRUE(r.due(t0 + milliseconds(40)));
  // Another event of the same save moves the settle time, not the first change.
  r.changed(t0 + milliseconds(30));
  EXPECT_FALSE(r.due(t0 + milliseconds(60)));
  EXPECT_TRUE(r.due(t0 + milliseconds(70)));
  EXPECT_EQ(r.first_change(), t0);
  EXPECT_FALSE(r.reload());  // the files do not exist: an error, and the change is consumed
  EXPECT_FALSE(r.due(t0 + milliseconds(1000)));
  EXPECT_THAT(r.error(), HasSubstr("unused.json"));
  r.changed(t0 + milliseconds(2000));
  EXPECT_EQ(r.first_change(), t0 + milliseconds(2000)) << "a new save starts a new measurement";
}

}  // namespace
}  // namespace meter::preview
