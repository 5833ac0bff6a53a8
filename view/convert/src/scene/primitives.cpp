// Primitives: each glTF primitive's accessors gathered per attribute (normals renormalised,
// tangent handedness snapped to +-1, weights renormalised), its indices turned into a triangle
// list, flat normals where lit shading has none, then interleaved into the runtime vertex record.
#include "convert_context.hpp"
#include "meter/shadergen/shadergen.hpp"
#include "scene/vertex_layout.hpp"

namespace meter::convert {

using shadergen::AttributeSemantic;
using shadergen::TextureSlot;

namespace {

Primitive convert_primitive(ConvertContext& ctx, std::size_t mi, std::size_t pi, const Material& material, int material_index) {
  const auto& prim = ctx.m.meshes[mi].primitives[pi];
  const std::string pp = idx("meshes", mi) + idx(".primitives", pi);
  RawPrimitive raw;
  auto add = [&](AttributeSemantic s, int index, int comps, std::vector<float> data) {
    raw.attrs[{int(s), index}] = {comps, std::move(data)};
  };
  const int pos = prim.attributes.at("POSITION");
  raw.vcount = ctx.m.accessors[static_cast<std::size_t>(pos)].count;
  add(AttributeSemantic::Position, -1, 3, ctx.attribute(pos, 3));
  auto has = [&](const char* n) { return prim.attributes.count(n) > 0; };
  if (has("NORMAL")) {
    auto n = ctx.attribute(prim.attributes.at("NORMAL"), 3);
    for (std::size_t v = 0; v < raw.vcount; ++v) {
      glm::vec3 x(n[v * 3], n[v * 3 + 1], n[v * 3 + 2]);
      x = glm::normalize(x);
      n[v * 3] = x.x, n[v * 3 + 1] = x.y, n[v * 3 + 2] = x.z;
    }
    add(AttributeSemantic::Normal, -1, 3, std::move(n));
  }
  if (has("TANGENT") && material.texture[int(TextureSlot::Normal)] >= 0) {
    auto t = ctx.attribute(prim.attributes.at("TANGENT"), 4);
    for (std::size_t v = 0; v < raw.vcount; ++v) t[v * 4 + 3] = t[v * 4 + 3] < 0 ? -1.0f : 1.0f;
    add(AttributeSemantic::Tangent, -1, 4, std::move(t));
  }
  if (has("TEXCOORD_0")) add(AttributeSemantic::TexCoord0, -1, 2, ctx.attribute(prim.attributes.at("TEXCOORD_0"), 2));
  if (has("TEXCOORD_1")) add(AttributeSemantic::TexCoord1, -1, 2, ctx.attribute(prim.attributes.at("TEXCOORD_1"), 2));
  if (has("COLOR_0")) add(AttributeSemantic::Color0, -1, 4, ctx.attribute(prim.attributes.at("COLOR_0"), 4, true));
  if (has("JOINTS_0") && has("WEIGHTS_0")) {
    add(AttributeSemantic::Joints0, -1, 4, ctx.attribute(prim.attributes.at("JOINTS_0"), 4));
    auto w = ctx.attribute(prim.attributes.at("WEIGHTS_0"), 4);
    for (std::size_t v = 0; v < raw.vcount; ++v) {
      float sum = w[v * 4] + w[v * 4 + 1] + w[v * 4 + 2] + w[v * 4 + 3];
      if (sum > 0) {
        for (int c = 0; c < 4; ++c) w[v * 4 + std::size_t(c)] /= sum;
      } else {
        w[v * 4] = 1.0f;  // no influence at all: bind to the first joint rather than collapse to 0
      }
    }
    add(AttributeSemantic::Weights0, -1, 4, std::move(w));
  }
  for (std::size_t ti = 0; ti < prim.targets.size(); ++ti) {
    const auto& t = prim.targets[ti];
    auto p = t.find("POSITION");
    add(AttributeSemantic::MorphPosition, int(ti), 3, p != t.end() ? ctx.attribute(p->second, 3) : std::vector<float>(raw.vcount * 3, 0.0f));
    auto n = t.find("NORMAL");
    if (n != t.end() && raw.attrs.count({int(AttributeSemantic::Normal), -1})) add(AttributeSemantic::MorphNormal, int(ti), 3, ctx.attribute(n->second, 3));
  }
  // Indices -> triangle list, degenerate triangles dropped.
  std::vector<std::uint32_t> src;
  if (prim.indices >= 0) {
    for (double v : ctx.accessor_values[static_cast<std::size_t>(prim.indices)]) src.push_back(static_cast<std::uint32_t>(v));
  } else {
    for (std::size_t v = 0; v < raw.vcount; ++v) src.push_back(static_cast<std::uint32_t>(v));
  }
  std::vector<std::uint32_t> tris = triangle_list(src, prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP ? TriangleMode::Strip
                                                       : prim.mode == TINYGLTF_MODE_TRIANGLE_FAN ? TriangleMode::Fan
                                                                                                 : TriangleMode::List);
  // Lit shading without NORMAL: glTF says compute flat normals, which needs unshared vertices.
  if (!raw.attrs.count({int(AttributeSemantic::Normal), -1}) && material.shading != shadergen::ShadingModel::Unlit) {
    raw = with_flat_normals(raw, tris);
    ctx.repair(pp + ".attributes", "no NORMAL for lit shading: flat normals computed (glTF 3.7.2.1)");
  } else {
    raw.indices = std::move(tris);
  }
  return interleave(std::move(raw), material_index, static_cast<int>(prim.targets.size()));
}

}  // namespace

void convert_meshes(ConvertContext& ctx, int default_material, Scene& s) {
  for (std::size_t mi = 0; mi < ctx.m.meshes.size(); ++mi) {
    const auto& mesh = ctx.m.meshes[mi];
    Mesh out;
    out.name = mesh.name.empty() ? "mesh" + std::to_string(mi) : mesh.name;
    for (double w : mesh.weights) out.weights.push_back(static_cast<float>(w));
    for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const int mat = mesh.primitives[pi].material >= 0 ? mesh.primitives[pi].material : default_material;
      out.primitives.push_back(convert_primitive(ctx, mi, pi, s.materials[static_cast<std::size_t>(mat)], mat));
    }
    if (out.weights.empty() && !out.primitives.empty()) out.weights.assign(static_cast<std::size_t>(out.primitives[0].morph_targets), 0.0f);
    s.meshes.push_back(std::move(out));
  }
}

}  // namespace meter::convert
