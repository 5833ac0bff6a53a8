// Cheaper levels of a converted scene's draws (meter/bridge/draw_levels.hpp), what the frame-rate
// governor draws when the full scene does not fit the frame time (docs/engine.md, "Quality levels"):
//
//   LOD levels      per primitive, meshoptimizer's simplifier at each error bound in turn (a
//                   fraction of the mesh extent); a level is kept only when it drops at least
//                   min_saving of the triangles of the level before it; the error reached and the
//                   triangle fraction are recorded. Primitives with morph targets get none (the
//                   error is measured on the rest pose only).
//   shading levels  per draw, every shading model below the converted one (Blinn-Phong, Gouraud,
//                   Flat, Unlit, in that order) whose program differs from the ones before it;
//                   the program keeps every other feature (vertex alpha of merged groups, skin,
//                   morphs, alpha mode), and a PBR material gets its Blinn-Phong-style parameters.
//                   A merged group's members get the same levels (one program per level).
//                   A primitive some draw shades Flat gets its Flat lists (flat_geometry.hpp):
//                   faces lit once, at a provoking vertex carrying the face normal.
//
// Safety items get no levels: every draw under a node or with a material that the integrity
// table or a safety binding of the config names (safety_draws).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/convert/vocabulary.hpp"
#include "meter/shadergen/program_cache.hpp"

namespace meter::convert {

struct LevelOptions {
  std::vector<float> lod_errors{0.01f, 0.04f};  // error bounds, increasing, fractions of the mesh extent
  float min_saving = 0.25f;                     // a kept LOD drops >= this share of the previous level's triangles
  bool shading = true;                          // make shading levels
  bool optimize = true;                         // shader optimizer on the level programs (scene constants, not the material's)
  shadergen::ProgramCache* program_cache = nullptr;  // optimized programs from earlier runs; null: this run's only
};

struct LevelsReport {
  int draws = 0, safety_draws = 0;
  int primitives = 0, primitives_with_lods = 0;
  int lod_levels = 0;                  // LOD levels stored, over all primitives
  std::vector<int> draws_at_lod;       // [k]: non-safety draws with at least k + 1 LOD levels
  std::vector<double> triangle_fraction_at_lod;  // [k]: their triangles at LOD k + 1 / at LOD 0
  std::size_t triangles = 0;           // LOD 0 triangles of the non-safety draws
  int programs_added = 0;              // shading-level programs (deduplicated)
  int draws_with_shadings = 0, shading_levels = 0;
  int shadings_skipped_identical = 0;  // a lower model whose program equals a kept one
  int flat_primitives = 0;             // primitives given Flat lists (meter/convert/flat_geometry.hpp)
  std::uint64_t flat_vertices = 0, flat_vertices_added = 0;  // their vertices, and the face-normal copies added
  double milliseconds = 0.0;           // wall time of make_levels
};

// Per draw: true when the draw is a safety item (its node or an ancestor is a region's node or a
// safety binding's node, or the node an animation of a safety animation binding rotates; or its
// material is a region's or a safety colour / emissive binding's), or when it can be on screen
// where a lamp or a readout is (its extent over every animation overlaps a safety lamp's draw or a
// telltale / readout region): what those checks compare includes its pixels.
std::vector<char> safety_draws(const Scene& scene);

// Adds the levels to `scene` (Primitive::lods, Scene::draw_levels, programs appended). Run after
// the integrity measurement (it reads the integrity table). Throws SceneError naming the draw when
// the shader generator rejects a level's features.
LevelsReport make_levels(Scene& scene, const LevelOptions& options = {});

// The `meter-convert --report` block: totals, then one line per draw with levels (node, shadings,
// LOD triangle fractions and errors).
std::string levels_report(const Scene& scene, const LevelsReport& report);

}  // namespace meter::convert
