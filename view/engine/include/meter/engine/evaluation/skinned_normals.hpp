// Normals of a skinned mesh as the authoring tool shades it: recomputed from the deformed surface.
//
// Linear blend skinning carries each rest normal by its vertex's blended joint matrix,
// mat3(sum w_k J_k) * n. Where the weights change across the surface (a bend's blend zone) that is
// not the normal of the deformed surface: the deformation's gradient also holds the weights'
// gradient, which the blended matrix leaves out. Blender's armature modifier deforms the vertices
// and then computes the normals of the deformed mesh (each face's normal weighted by its corner
// angle at the vertex), and that is what the artist sees. Measured on the skinning feature scene
// (docs/fidelity.md): the engine's render of the mesh Blender deformed, drawn without skinning,
// is 44.5 dB from the reference over object pixels; skinned with LBS normals 33.0 dB.
//
// The vertex shader keeps doing the skinning (positions, tangents, and n = mat3(S) * a_normal).
// What changes is the a_normal it is given: per vertex, inverse(mat3(S)) * n_deformed, so that the
// shader's own product yields the deformed surface's normal exactly, with no program of its own.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// What stays fixed for a primitive: vertices that are one point of the surface (the same rest
// position and rest normal: copies split by texture seams) share their normal.
struct SkinnedNormalsLayout {
  int position = -1, normal = -1, joints = -1, weights = -1;  // float offsets in the vertex record
  std::vector<std::uint32_t> point;  // vertex -> index of the surface point it belongs to
  std::uint32_t points = 0;
};

// Whether the primitive's normals can be recomputed: POSITION, NORMAL, JOINTS_0 and WEIGHTS_0
// present and no morph targets (their deltas would have to be applied first; such primitives keep
// the blended-matrix normals).
bool has_skinned_normals(const Primitive& prim);

// The layout of a primitive for which has_skinned_normals() holds.
SkinnedNormalsLayout skinned_normals_layout(const Primitive& prim);

// The joint matrices the vertex shader gets (u_joint_matrices): joint j takes the rest pose into
// the mesh node's space, inverse(model) * world(joint j) * inverse_bind(j). One joint, given
// inverse(model), without allocating (the draw loop), and all of them.
glm::mat4 joint_matrix(const Skin& skin, std::size_t j, std::span<const glm::mat4> world, const glm::mat4& inverse_model);
std::vector<glm::mat4> joint_matrices(const Skin& skin, std::span<const glm::mat4> world, const glm::mat4& model);

// Writes into `vertices` (a copy of prim.vertices, same record layout) the NORMAL of every vertex:
// the value the shader's skinning turns into the deformed surface's normal. Returns how many
// vertices kept their rest normal because no deformed normal exists there (every face around
// them degenerate, or a blended matrix that cannot be inverted): those are shaded as LBS shades
// them, and nothing is NaN.
std::size_t skin_normals(const Primitive& prim, const SkinnedNormalsLayout& layout, std::span<const glm::mat4> joints,
                         std::span<float> vertices);

}  // namespace meter::engine
