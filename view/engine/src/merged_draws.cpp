#include "meter/engine/merged_draws.hpp"

#include <algorithm>
#include <set>

#include <glm/gtc/matrix_inverse.hpp>

namespace meter::engine {

using bridge::AttributeSemantic;

std::string vertex_layout_key(const Primitive& p) {
  std::string k = std::to_string(p.stride);
  for (const auto& a : p.layout) k += "|" + std::to_string(int(a.semantic)) + "." + std::to_string(a.index) + "." + std::to_string(a.components) + "." + std::to_string(a.offset);
  return k;
}

std::string check_groups(const Scene& s) {
  std::set<int> seen;
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const auto& mg = s.groups[g];
    const std::string p = "groups[" + std::to_string(g) + "] (\"" + mg.name + "\"): ";
    if (mg.draws.empty()) return p + "no draws";
    int program = -1;
    std::string layout;
    for (int d : mg.draws) {
      if (d < 0 || static_cast<std::size_t>(d) >= s.draws.size()) return p + "draw index " + std::to_string(d) + " out of range";
      if (!seen.insert(d).second) return p + "draw " + std::to_string(d) + " is in two groups";
      const DrawItem& di = s.draws[static_cast<std::size_t>(d)];
      const Primitive& prim = s.meshes[static_cast<std::size_t>(di.mesh)].primitives[static_cast<std::size_t>(di.primitive)];
      if (program < 0) program = di.program, layout = vertex_layout_key(prim);
      if (di.program != program) return p + "members use different programs";
      if (vertex_layout_key(prim) != layout) return p + "members have different vertex layouts";
      if (prim.morph_targets > 0 || s.nodes[static_cast<std::size_t>(di.node)].skin >= 0) return p + "a member is skinned or morphed";
    }
    const auto& prog = s.programs[static_cast<std::size_t>(program)].program;
    if (std::none_of(prog.attributes.begin(), prog.attributes.end(), [](const auto& a) { return a.semantic == AttributeSemantic::VertexAlpha; })) {
      return p + "the program has no vertex alpha attribute";
    }
    if (prog.features.skin_joints > 0 || prog.features.morph_targets > 0) return p + "the program skins or morphs";
  }
  return "";
}

void transform_member(const Primitive& src, const glm::mat4& world, float alpha, std::span<float> dst) {
  const int out_stride = merged_stride(src);
  const glm::mat3 normal = glm::inverseTranspose(glm::mat3(world));
  const glm::mat3 linear(world);
  for (std::uint32_t v = 0; v < src.vertex_count; ++v) {
    const float* in = src.vertices.data() + std::size_t(v) * std::size_t(src.stride);
    float* out = dst.data() + std::size_t(v) * std::size_t(out_stride);
    std::copy(in, in + src.stride, out);
    for (const auto& a : src.layout) {
      float* o = out + a.offset;
      const float* i = in + a.offset;
      if (a.semantic == AttributeSemantic::Position) {
        const glm::vec4 p = world * glm::vec4(i[0], i[1], i[2], 1.0f);
        o[0] = p.x, o[1] = p.y, o[2] = p.z;
      } else if (a.semantic == AttributeSemantic::Normal) {
        const glm::vec3 n = normal * glm::vec3(i[0], i[1], i[2]);
        o[0] = n.x, o[1] = n.y, o[2] = n.z;
      } else if (a.semantic == AttributeSemantic::Tangent) {
        const glm::vec3 t = linear * glm::vec3(i[0], i[1], i[2]);
        o[0] = t.x, o[1] = t.y, o[2] = t.z;
      }
    }
    out[src.stride] = alpha;
  }
}

void set_member_alpha(const Primitive& src, float alpha, std::span<float> dst) {
  const int out_stride = merged_stride(src);
  for (std::uint32_t v = 0; v < src.vertex_count; ++v) dst[std::size_t(v) * std::size_t(out_stride) + std::size_t(src.stride)] = alpha;
}

void append_member_indices(const Primitive& src, std::uint32_t base, bool mirror, std::vector<std::uint32_t>& out) {
  append_member_indices(std::span<const std::uint32_t>(src.indices), base, mirror, out);
}

void append_member_indices(std::span<const std::uint32_t> indices, std::uint32_t base, bool mirror, std::vector<std::uint32_t>& out) {
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    if (mirror) {
      out.insert(out.end(), {base + indices[i], base + indices[i + 2], base + indices[i + 1]});
    } else {
      out.insert(out.end(), {base + indices[i], base + indices[i + 1], base + indices[i + 2]});
    }
  }
}

}  // namespace meter::engine
