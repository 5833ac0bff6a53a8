#include "programs/program_features.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "meter/engine/evaluation/animation.hpp"

namespace meter::convert {

using shadergen::AttributeSemantic;
using shadergen::TextureSlot;
using engine::Pose;

shadergen::MaterialFeatures draw_features(const Scene& s, const Node& node, const Primitive& prim,
                                          const shadergen::LightCounts& lights, bool vertex_alpha) {
  const Material& mat = s.materials[static_cast<std::size_t>(prim.material)];
  shadergen::MaterialFeatures f;
  f.shading = mat.shading;
  f.alpha = mat.alpha;
  auto has_attr = [&](AttributeSemantic a) {
    return std::any_of(prim.layout.begin(), prim.layout.end(), [&](const VertexAttribute& v) { return v.semantic == a; });
  };
  auto tex = [&](TextureSlot slot) {
    const int k = int(slot);
    if (mat.texture[k] < 0) return false;
    if (!has_attr(mat.texcoord[k] == 1 ? AttributeSemantic::TexCoord1 : AttributeSemantic::TexCoord0)) return false;
    if (mat.texcoord[k] == 1) f.texcoord1_slots |= 1u << k;
    return true;
  };
  const bool lit = mat.shading != shadergen::ShadingModel::Unlit;
  const bool per_pixel = mat.shading == shadergen::ShadingModel::Flat || mat.shading == shadergen::ShadingModel::BlinnPhong ||
                         mat.shading == shadergen::ShadingModel::PbrMetallicRoughness;
  f.base_color_texture = tex(TextureSlot::BaseColor);
  f.metallic_roughness_texture = mat.shading == shadergen::ShadingModel::PbrMetallicRoughness && tex(TextureSlot::MetallicRoughness);
  f.normal_texture = per_pixel && tex(TextureSlot::Normal);
  f.emissive_texture = tex(TextureSlot::Emissive);
  f.occlusion_texture = lit && tex(TextureSlot::Occlusion);
  f.texture_transform = mat.has_uv_transform && (f.base_color_texture || f.metallic_roughness_texture || f.normal_texture ||
                                                  f.emissive_texture || f.occlusion_texture);
  f.vertex_colors = has_attr(AttributeSemantic::Color0);
  f.double_sided = mat.double_sided;
  if (node.skin >= 0 && has_attr(AttributeSemantic::Joints0)) f.skin_joints = static_cast<int>(s.skins[static_cast<std::size_t>(node.skin)].joints.size());
  f.morph_targets = prim.morph_targets;
  f.morph_normals = has_attr(AttributeSemantic::MorphNormal);
  f.lights = lit ? lights : shadergen::LightCounts{};
  // Only scenes that name an environment get it, and only on models that can use it.
  f.environment_map_2d = s.environment.present() && (mat.shading == shadergen::ShadingModel::BlinnPhong ||
                                                     mat.shading == shadergen::ShadingModel::PbrMetallicRoughness);
  f.has_tangents = f.normal_texture && has_attr(AttributeSemantic::Tangent);
  // Concatenated members: visibility becomes vertex alpha. The unmerged draw of the same
  // node feeds a constant 1 (Renderer), so one program serves both ways of drawing.
  f.vertex_alpha = vertex_alpha;
  return f;
}

std::vector<char> dynamic_nodes(const Scene& s) {
  std::vector<char> animated(s.nodes.size(), 0), dyn(s.nodes.size(), 0);
  for (const auto& a : s.animations) {
    for (const auto& ch : a.channels) animated[static_cast<std::size_t>(ch.node)] = 1;
  }
  for (const auto& sc : s.config.scripts)  // a script's translation / rotation moves its node
    for (const auto& o : sc.outputs)
      if (o.kind == ScriptOutputKind::Translation || o.kind == ScriptOutputKind::Rotation)
        if (const int n = s.find_node(o.target); n >= 0) animated[static_cast<std::size_t>(n)] = 1;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    for (int n = static_cast<int>(i); n >= 0; n = s.nodes[static_cast<std::size_t>(n)].parent) {
      if (animated[static_cast<std::size_t>(n)]) dyn[i] = 1;
    }
  }
  return dyn;
}

shadergen::ConstantValues folding_constants(const Scene& s, const Material& m, bool fold_material, const std::vector<int>& light_nodes,
                                            const std::vector<char>& dyn) {
  using U = shadergen::UniformSemantic;
  shadergen::ConstantValues cv;
  // A material that is not folded shares its program with every material of the same features
  // ("|dynmat"): then none of its parameters may be folded, or the draws would all get the
  // parameters of the material that made the program first (the runtime sets them per draw).
  if (fold_material) {
    cv.set(U::BaseColorFactor, {m.base_color.r, m.base_color.g, m.base_color.b, m.base_color.a});
    cv.set(U::EmissiveFactor, {m.emissive.r, m.emissive.g, m.emissive.b});
    cv.set(U::MetallicFactor, {m.metallic});
    cv.set(U::RoughnessFactor, {m.roughness});
    cv.set(U::NormalScale, {m.normal_scale});
    cv.set(U::OcclusionStrength, {m.occlusion_strength});
    cv.set(U::AlphaCutoff, {m.alpha_cutoff});
    cv.set(U::SpecularColor, {m.specular_color.r, m.specular_color.g, m.specular_color.b});
    cv.set(U::Shininess, {m.shininess});
  }
  cv.set(U::AmbientLight, {s.ambient.r, s.ambient.g, s.ambient.b});
  // A brightness signal changes the exposure at runtime: then it stays a uniform.
  const bool dimmable = s.config.features.theme && !s.config.features.theme->brightness_signal.empty();
  if (!dimmable) cv.set(U::Exposure, {static_cast<float>(std::exp2(s.config.exposure))});
  cv.set(U::EnvironmentIntensity, {s.environment.strength});
  for (int a = 0; a < 6; ++a) {
    const glm::vec3& e = s.environment.irradiance[std::size_t(a)];
    cv.set(U::EnvironmentIrradiance, a, {e.r, e.g, e.b});
  }
  for (int k = 0; k < 5 && fold_material; ++k) {
    const glm::mat3& t = m.uv_transform[std::size_t(k)];
    cv.set(U::TextureTransform, k, std::vector<float>(glm::value_ptr(t), glm::value_ptr(t) + 9));
  }
  // Lights: colour, intensity, range and cones never change at runtime; position and direction
  // come from node transforms, folded only when the light node cannot move (no animated ancestor).
  Pose rest = Pose::rest(s);
  std::vector<glm::mat4> world;
  engine::world_matrices(s, rest, world);
  for (std::size_t i = 0; i < light_nodes.size(); ++i) {
    const int g = static_cast<int>(i);
    const int n = light_nodes[i];
    const Light& l = s.lights[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(n)].light)];
    cv.set(U::LightColor, g, {l.color.r, l.color.g, l.color.b});
    cv.set(U::LightIntensity, g, {l.intensity});
    cv.set(U::LightRange, g, {l.range});
    cv.set(U::LightInnerConeCos, g, {std::cos(l.inner_cone)});
    cv.set(U::LightOuterConeCos, g, {std::cos(l.outer_cone)});
    if (!dyn[static_cast<std::size_t>(n)]) {
      const glm::mat4& w = world[static_cast<std::size_t>(n)];
      glm::vec3 pos(w[3]);
      glm::vec3 dir = glm::normalize(glm::vec3(w * glm::vec4(0, 0, -1, 0)));  // lights point down -Z
      cv.set(U::LightPosition, g, {pos.x, pos.y, pos.z});
      cv.set(U::LightDirection, g, {dir.x, dir.y, dir.z});
    }
  }
  return cv;
}

shadergen::LightCounts count_lights(const Scene& s, const std::vector<int>& light_nodes) {
  shadergen::LightCounts lights;
  lights.shadows = shadow_map_lights(s, light_nodes);
  for (int n : light_nodes) {
    switch (s.lights[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(n)].light)].type) {
      case LightType::Directional: ++lights.directional; break;
      case LightType::Point: ++lights.point; break;
      case LightType::Spot: ++lights.spot; break;
    }
  }
  return lights;
}

namespace {
bool has_attr(const Primitive& p, AttributeSemantic a) {
  return std::any_of(p.layout.begin(), p.layout.end(), [&](const VertexAttribute& v) { return v.semantic == a; });
}
}  // namespace

shadergen::MaterialFeatures features_at(const Scene& s, const DrawItem& d, const shadergen::MaterialFeatures& stored,
                                        shadergen::ShadingModel shading, shadergen::Precision precision) {
  using shadergen::ShadingModel;
  const Primitive& prim = s.meshes[std::size_t(d.mesh)].primitives[std::size_t(d.primitive)];
  const Material& mat = s.materials[std::size_t(prim.material)];
  shadergen::MaterialFeatures f = stored;
  f.shading = shading;
  f.precision = precision;
  f.texcoord1_slots = 0;
  auto tex = [&](TextureSlot slot) {
    const int k = int(slot);
    if (mat.texture[std::size_t(k)] < 0) return false;
    const bool uv1 = mat.texcoord[std::size_t(k)] == 1;
    if (!has_attr(prim, uv1 ? AttributeSemantic::TexCoord1 : AttributeSemantic::TexCoord0)) return false;
    if (uv1) f.texcoord1_slots |= 1u << k;
    return true;
  };
  const bool lit = shading != ShadingModel::Unlit;
  // Normal maps need an interpolated per-pixel normal: shadergen accepts them on Blinn-Phong and PBR only.
  const bool per_pixel = shading == ShadingModel::BlinnPhong || shading == ShadingModel::PbrMetallicRoughness;
  f.base_color_texture = tex(TextureSlot::BaseColor);
  f.metallic_roughness_texture = shading == ShadingModel::PbrMetallicRoughness && tex(TextureSlot::MetallicRoughness);
  f.normal_texture = per_pixel && tex(TextureSlot::Normal);
  f.emissive_texture = tex(TextureSlot::Emissive);
  f.occlusion_texture = lit && tex(TextureSlot::Occlusion);
  f.texture_transform = mat.has_uv_transform && (f.base_color_texture || f.metallic_roughness_texture || f.normal_texture ||
                                                  f.emissive_texture || f.occlusion_texture);
  f.has_tangents = f.normal_texture && has_attr(prim, AttributeSemantic::Tangent);
  // The environment map needs a per-pixel normal too; cheaper models fall back to the config's
  // uniform ambient (for an environment scene: the map's mean radiance).
  f.environment_map_2d = per_pixel && s.environment.present();
  if (lit) {
    // The scene's lights, counted as the converter counts them.
    f.lights = count_lights(s, light_order(s));
  } else {
    f.lights = {};
  }
  return shadergen::canonical(f);
}


PhongParameters pbr_as_phong(const Material& m) {
  PhongParameters p;
  const float a = std::max(m.roughness * m.roughness, 0.02f);
  p.shininess = std::clamp(2.0f / (a * a) - 2.0f, 1.0f, 2048.0f);
  const float metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  p.specular_color = glm::mix(glm::vec3(0.04f), glm::vec3(m.base_color), metallic);
  p.base_scale = 1.0f - metallic;
  return p;
}

}  // namespace meter::convert
