// The geometry a Flat program needs (Keio's flat rung: lighting computed once per face). A Flat
// program lights each vertex with its own normal and hands the result on without interpolation,
// so every fragment of a triangle takes the light of its provoking vertex (the last one, in GLES).
// The converter therefore gives each triangle a provoking vertex whose normal is the face normal:
// a corner whose own normal already is (within kFlatNormalCos), else a copy of a corner with the
// face normal, appended to the primitive's vertices. The Flat lists rotate each triangle (winding
// kept) so that vertex comes last. The other lists and the vertices they use are left as they
// were, so every non-Flat draw is unchanged.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

// A corner's own normal serves as the face normal when their cosine is at least this (2.6 deg).
constexpr float kFlatNormalCos = 0.999f;

struct FlatFaces {
  std::vector<std::uint32_t> copied_from;  // per appended vertex: the vertex whose record it copies
  std::vector<glm::vec3> copy_normals;     // per appended vertex: its normal (the face's)
  std::vector<std::vector<std::uint32_t>> lists;  // per input list: its triangles as Flat draws them
};

// Pure: `positions` and `normals` per vertex (unit normals), `lists` triangle lists over them.
// Appended vertices are numbered from positions.size() and shared by the faces (of any list) whose
// normal they carry. The face normal is the triangle's geometric normal, turned to the side its
// corners' normals point to; a degenerate triangle keeps its order and its last corner.
FlatFaces flat_faces(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     const std::vector<std::span<const std::uint32_t>>& lists);

// Gives `prim` its Flat lists (Primitive::flat_indices, LodLevel::flat_indices) where they are
// missing, appending the copies to its vertices. Returns the vertices added; a primitive without
// POSITION and NORMAL, or a skinned one (its normals follow the pose at run time), gets none.
std::uint32_t prepare_flat_geometry(Primitive& prim);

struct FlatGeometryReport {
  int primitives = 0;          // primitives with Flat lists
  std::uint64_t vertices = 0;  // their vertices before
  std::uint64_t added = 0;     // copies appended
};

// prepare_flat_geometry on every primitive a Flat program draws (a draw's own program or one of
// its shading levels).
FlatGeometryReport prepare_flat_draws(Scene& scene);

}  // namespace meter::convert
