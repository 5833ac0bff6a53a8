// Cheaper levels of the scene's draws, made at conversion (view/convert/src/levels/) and stored in
// the package, so the runtime can draw a draw unit more cheaply when the frame-rate governor asks
// (meter/engine/governor/quality_choice.hpp) without a shader generator or a simplifier:
//
//   LOD levels      simplified index lists over a primitive's own vertices (meshoptimizer's
//                   simplifier at a stated error bound), with the error reached and the share of
//                   triangles kept;
//   shading levels  per draw, programs generated with a lower shading model than the converted
//                   one (Blinn-Phong, Gouraud, Flat, Unlit), each with the material parameters that
//                   model reads (a PBR material shown Blinn-Phong-style gets a mapped specular colour
//                   and shininess, and its diffuse colour scaled for metals).
//
// Level 0 is always the scene as converted and is not stored here: Primitive::indices and the
// draw's own program. Safety items (telltales, anything the integrity table checks) get no levels.
// Plain data only.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "meter/bridge/program.hpp"

namespace meter::bridge {

// One simplified version of a primitive: level k of Primitive::lods is LOD k + 1.
struct LodLevel {
  float error = 0.0f;              // meshoptimizer's relative error (fraction of the mesh extent)
  float triangle_fraction = 1.0f;  // triangles kept / the full primitive's triangles, in (0, 1)
  std::vector<std::uint32_t> indices;  // triangles over the primitive's vertices (each < vertex_count)
  std::vector<std::uint32_t> flat_indices{};  // the same triangles for Flat programs (Primitive::flat_indices)
  bool operator==(const LodLevel&) const = default;
};

// One cheaper shading of a draw: level k of DrawLevels::shadings is shading level k + 1.
struct ShadingLevel {
  ShadingModel shading = ShadingModel::Unlit;  // lower than the draw's own program's model
  int program = -1;                            // index into Scene::programs
  // The material parameters this model reads, in place of the material's own: for a PBR material
  // shown with Blinn-Phong / Gouraud / Flat, the mapped specular colour and shininess; the base
  // colour's rgb (after any binding override) is multiplied by base_scale (1 - metallic: a metal's
  // diffuse is black). A non-PBR material keeps its own values (base_scale 1).
  glm::vec3 specular_color{0.5f};
  float shininess = 32.0f;
  float base_scale = 1.0f;
  bool operator==(const ShadingLevel&) const = default;
};

// The levels one draw may take. Scene::draw_levels has one per Scene::draws entry, or is empty
// (a package converted with --levels=off, or a scene built in memory): every draw at level 0.
struct DrawLevels {
  bool safety = false;                 // a safety item: never simplified (no shadings, lods = 0)
  std::vector<ShadingLevel> shadings;  // cheaper shadings, most expensive first
  int lods = 0;                        // how many of its primitive's Primitive::lods it may use
  bool operator==(const DrawLevels&) const = default;
};

}  // namespace meter::bridge
