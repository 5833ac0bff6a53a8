// The levels stage of the converter (meter/convert/levels.hpp) on the cluster and on hand-built
// meshes: safety items get none, every LOD level keeps its error bound and saves at least a quarter
// of the triangles of the level before, every shading level is a lower model with its own program
// that keeps what merged groups need, and the levels survive the package round trip.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "meter/convert/levels.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;

namespace {

const Scene& cluster_with_levels() {
  static const Scene s = [] {
    Scene c = engine::test::cluster_scene();
    make_levels(c);
    return c;
  }();
  return s;
}

// An n x n grid of quads in the XY plane, flat: the simplifier can take it down to two triangles
// at any error bound.
Primitive grid(int n) {
  Primitive p;
  p.material = 0;
  p.stride = 6;
  p.layout = {{AttributeSemantic::Position, -1, 3, 0}, {AttributeSemantic::Normal, -1, 3, 3}};
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) p.vertices.insert(p.vertices.end(), {float(x) / n, float(y) / n, 0, 0, 0, 1});
  p.vertex_count = std::uint32_t((n + 1) * (n + 1));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::uint32_t a = std::uint32_t(y * (n + 1) + x), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
      p.indices.insert(p.indices.end(), {a, b, d, a, d, c});
    }
  p.bounds_max = glm::vec3(1, 1, 0);
  return p;
}

// One node drawing `prim` with a PBR program (no GL needed: make_levels with shading off).
Scene one_draw(Primitive prim) {
  Scene s;
  s.source_name = "hand-built";
  Node n;
  n.name = "Part";
  n.mesh = 0;
  s.nodes = {n};
  s.roots = {0};
  Mesh m;
  m.primitives = {std::move(prim)};
  s.meshes = {m};
  s.materials = {Material{}};
  s.programs = {ProgramEntry{}};
  s.draws = {{0, 0, 0, 0}};
  return s;
}

}  // namespace

TEST(Levels, SafetyDrawsGetNoLevels) {
  const Scene& s = cluster_with_levels();
  const std::vector<char> safety = safety_draws(s);
  ASSERT_EQ(s.draw_levels.size(), s.draws.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    EXPECT_EQ(bool(s.draw_levels[i].safety), bool(safety[i])) << "draw " << i;
    if (!safety[i]) continue;
    ++n;
    EXPECT_TRUE(s.draw_levels[i].shadings.empty()) << "draw " << i;
    EXPECT_EQ(s.draw_levels[i].lods, 0) << "draw " << i;
  }
  EXPECT_GT(n, 0u);
  // Every node a safety visibility binding shows (a telltale) is drawn as a safety item, and so is
  // each needle an animation binding rotates.
  int telltales = 0;
  for (const auto& b : s.config.bindings) {
    if (b.kind != BindingKind::Visibility || !b.safety) continue;
    const int node = s.find_node(b.node);
    bool drawn = false, covered = true;
    for (std::size_t i = 0; i < s.draws.size(); ++i) {
      int n2 = s.draws[i].node;
      while (n2 >= 0 && n2 != node) n2 = s.nodes[std::size_t(n2)].parent;
      if (n2 == node) drawn = true, covered = covered && safety[i];
    }
    if (drawn) {
      ++telltales;
      EXPECT_TRUE(covered) << b.node << " (telltale) has a draw with levels";
    }
  }
  EXPECT_GT(telltales, 0);
}

// A draw under or behind a telltale is part of what the telltale's check sees: its window (the
// dark glass the lamp sits in) is the lamp's unlit look, so a cheaper window shading reads as a
// wrong lamp. Such draws keep full quality like the lamps themselves (the governor once lowered
// the cluster's telltale windows and the integrity monitor raised 15 faults on that frame).
TEST(Levels, DrawsBehindATelltaleAreSafetyItemsToo) {
  const Scene& s = cluster_with_levels();
  const std::vector<char> safety = safety_draws(s);
  int windows = 0;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    const std::string& name = s.nodes[std::size_t(s.draws[i].node)].name;
    if (name.rfind("TTWindow_", 0) != 0) continue;
    ++windows;
    EXPECT_TRUE(safety[i]) << name << " sits behind a telltale but would get levels";
  }
  EXPECT_GE(windows, 10);  // the cluster has a window behind each of its 17 lamps
}

TEST(Levels, LodLevelsKeepTheirBoundAndSaveAQuarter) {
  const Scene& s = cluster_with_levels();
  const LevelOptions o;
  int levels = 0;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      std::size_t previous = p.indices.size();
      float previous_error = 0.0f;
      for (const auto& l : p.lods) {
        ++levels;
        EXPECT_LE(l.error, o.lod_errors.back()) << m.name;
        EXPECT_GE(l.error, previous_error) << m.name << ": levels are in increasing error";
        // Kept only when at most 75 % of the level before's triangles are left.
        EXPECT_LE(double(l.indices.size()), 0.75 * double(previous)) << m.name;
        EXPECT_EQ(l.indices.size() % 3, 0u);
        EXPECT_FLOAT_EQ(l.triangle_fraction, float(double(l.indices.size() / 3) / double(p.indices.size() / 3)));
        for (auto i : l.indices) ASSERT_LT(i, p.vertex_count);
        previous = l.indices.size(), previous_error = l.error;
      }
    }
  EXPECT_GT(levels, 0) << "the cluster's dials and rings simplify";
}

TEST(Levels, AFlatGridKeepsOneLevelBecauseTheNextSavesNothing) {
  Scene s = one_draw(grid(16));
  LevelOptions o;
  o.shading = false;
  const LevelsReport r = make_levels(s, o);
  // At 1 % the flat grid collapses to (nearly) its two corner triangles; at 4 % nothing more goes,
  // so that level is dropped (< 25 % saved).
  ASSERT_EQ(s.meshes[0].primitives[0].lods.size(), 1u);
  EXPECT_LT(s.meshes[0].primitives[0].lods[0].triangle_fraction, 0.1f);
  EXPECT_EQ(s.draw_levels[0].lods, 1);
  EXPECT_EQ(r.lod_levels, 1);
  EXPECT_EQ(r.primitives_with_lods, 1);
  // Two triangles cannot lose a quarter: no level.
  Scene q = one_draw(engine::test::quad_primitive(0));
  make_levels(q, o);
  EXPECT_TRUE(q.meshes[0].primitives[0].lods.empty());
  EXPECT_EQ(q.draw_levels[0].lods, 0);
}

TEST(Levels, BadOptionsAreRefused) {
  Scene s = one_draw(grid(4));
  LevelOptions o;
  o.lod_errors = {0.04f, 0.01f};
  EXPECT_THROW(make_levels(s, o), SceneError);
  o.lod_errors = {0.01f};
  o.min_saving = 0.0f;
  EXPECT_THROW(make_levels(s, o), SceneError);
}

TEST(Levels, ShadingLevelsAreLowerModelsWithTheirOwnPrograms) {
  const Scene& s = cluster_with_levels();
  int with = 0;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    const bridge::Program& own = s.programs[std::size_t(s.draws[i].program)].program;
    int previous = int(own.features.shading);
    std::set<std::string> sources = {own.vertex_source + own.fragment_source};
    with += s.draw_levels[i].shadings.empty() ? 0 : 1;
    for (const auto& l : s.draw_levels[i].shadings) {
      ASSERT_GE(l.program, 0);
      ASSERT_LT(std::size_t(l.program), s.programs.size());
      const bridge::Program& p = s.programs[std::size_t(l.program)].program;
      EXPECT_LT(int(l.shading), previous) << "draw " << i << ": levels go down the models";
      EXPECT_EQ(p.features.shading, l.shading);
      EXPECT_EQ(p.features.vertex_alpha, own.features.vertex_alpha) << "draw " << i << ": merged members need vertex alpha";
      EXPECT_EQ(p.features.alpha, own.features.alpha);
      EXPECT_EQ(p.blend, own.blend);
      EXPECT_TRUE(sources.insert(p.vertex_source + p.fragment_source).second) << "draw " << i << ": a level draws as one before it";
      EXPECT_GE(l.base_scale, 0.0f);
      EXPECT_LE(l.base_scale, 1.0f);
      previous = int(l.shading);
    }
  }
  EXPECT_GT(with, 0);
  // The runtime's check agrees (groups share each level's program).
  EXPECT_EQ(engine::check_draw_levels(s), "");
}

TEST(Levels, MergedGroupsAreOneUnitWithTheirMembersLevels) {
  const Scene& s = cluster_with_levels();
  ASSERT_FALSE(s.groups.empty());
  const engine::DrawClasses classes = engine::classify_draws(s, true, -1);
  const engine::DrawUnits units = engine::make_draw_units(s, classes, true);
  std::size_t in_groups = 0;
  for (const auto& g : s.groups) in_groups += g.draws.size() - 1;
  EXPECT_EQ(units.ladders.size(), s.draws.size() - in_groups);
  for (std::size_t u = 0; u < units.ladders.size(); ++u) {
    const auto& l = units.ladders[u];
    ASSERT_EQ(l.lod_errors.size(), l.lod_triangle_fractions.size());
    EXPECT_EQ(l.lod_errors[0], 0.0f);
    EXPECT_EQ(l.lod_triangle_fractions[0], 1.0f);
    // Each LOD of a unit (a merged group too) drops at least a quarter of the triangles before it.
    for (std::size_t k = 1; k < l.lod_triangle_fractions.size(); ++k)
      EXPECT_LE(l.lod_triangle_fractions[k], 0.75f * l.lod_triangle_fractions[k - 1]) << l.name << " lod " << k;
    EXPECT_EQ(units.lod_steps[u].size(), l.lod_errors.size());
    if (l.safety) {
      EXPECT_EQ(l.shadings.size(), 1u) << l.name;
      EXPECT_EQ(l.lod_errors.size(), 1u) << l.name;
    }
    for (int m : units.members[u]) EXPECT_EQ(units.unit_of[std::size_t(m)], int(u));
  }
  int safety = 0, shaded = 0, lodded = 0;
  for (const auto& l : units.ladders) {
    safety += l.safety ? 1 : 0;
    shaded += l.shadings.size() > 1 ? 1 : 0;
    lodded += l.lod_errors.size() > 1 ? 1 : 0;
  }
  std::printf("[ levels   ] cluster: %zu draw units (%d safety), %d with cheaper shadings, %d with LODs\n", units.ladders.size(),
              safety, shaded, lodded);
  for (const auto& l : units.ladders)
    for (std::size_t k = 1; k < l.lod_errors.size(); ++k)
      std::printf("[ levels   ]   %s lod %zu: error %.4f, %.3f of its triangles\n", l.name.c_str(), k, double(l.lod_errors[k]),
                  double(l.lod_triangle_fractions[k]));
}

TEST(Levels, ClusterLevelsSurviveThePackageRoundTrip) {
  const Scene& s = cluster_with_levels();
  const Scene r = engine::deserialize_scene(serialize_scene(s), "cluster.msp");
  EXPECT_EQ(r.draw_levels, s.draw_levels);
  ASSERT_EQ(r.meshes.size(), s.meshes.size());
  for (std::size_t m = 0; m < s.meshes.size(); ++m)
    for (std::size_t p = 0; p < s.meshes[m].primitives.size(); ++p)
      EXPECT_EQ(r.meshes[m].primitives[p].lods, s.meshes[m].primitives[p].lods) << s.meshes[m].name;
  EXPECT_EQ(r.programs.size(), s.programs.size());
}

TEST(Levels, ReportListsEveryDrawsLevels) {
  Scene s = engine::test::cluster_scene();
  const LevelsReport r = make_levels(s);
  const std::string text = levels_report(s, r);
  EXPECT_NE(text.find("levels: " + std::to_string(s.draws.size()) + " draws (" + std::to_string(r.safety_draws) + " safety"),
            std::string::npos) << text;
  EXPECT_NE(text.find("lod 1: "), std::string::npos) << text;
  EXPECT_NE(text.find(" > blinn-phong (program "), std::string::npos) << text;
  EXPECT_NE(text.find(" safety\n"), std::string::npos) << text;
}
