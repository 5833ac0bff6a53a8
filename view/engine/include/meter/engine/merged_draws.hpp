// Mesh concatenation at runtime (the DENSO paper sec. 5.2, docs/concatenation.md): a group of
// objects that share a material is drawn as ONE draw. The runtime keeps one vertex array per group
// holding every member's vertices already transformed to world space by the CPU, a per-vertex
// alpha for visibility, and an index array holding only the visible members.
// Which objects may be merged is decided offline (meter/convert/concat_plan.hpp); these are the
// pure helpers the Renderer uses, unit-tested without GL, and the check the package reader runs.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// The vertex layout of a primitive as text ("stride|semantic.index.components.offset|..."):
// members of one group must have equal keys.
std::string vertex_layout_key(const Primitive& p);

// Checks a loaded scene's groups (package reader): indices in range, one program with the vertex
// alpha attribute and no skin/morph, equal layouts, no draw in two groups. Returns "" when fine.
std::string check_groups(const Scene& scene);

// Merged vertex record: the members' own record followed by one float, the vertex alpha.
inline int merged_stride(const Primitive& p) { return p.stride + 1; }

// Writes `src`'s vertices transformed by `world` into dst (vertex_count * merged_stride floats):
// POSITION by world, NORMAL by the inverse transpose (not normalised: the shader normalises, as it
// does for the unmerged draw), TANGENT xyz by the upper 3x3 (w kept), everything else copied;
// the appended alpha = `alpha`.
void transform_member(const Primitive& src, const glm::mat4& world, float alpha, std::span<float> dst);

// Rewrites only the alpha float of each vertex in dst.
void set_member_alpha(const Primitive& src, float alpha, std::span<float> dst);

// Appends src's triangles offset by `base`; reversed winding when `mirrored` (the world matrix has
// a negative determinant: the unmerged draw flips glFrontFace instead, the merged draw cannot).
void append_member_indices(const Primitive& src, std::uint32_t base, bool mirrored, std::vector<std::uint32_t>& out);
// The same for one of the primitive's index lists (a LOD level's, meter/bridge/draw_levels.hpp).
void append_member_indices(std::span<const std::uint32_t> indices, std::uint32_t base, bool mirrored,
                           std::vector<std::uint32_t>& out);

}  // namespace meter::engine
