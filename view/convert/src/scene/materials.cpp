// Materials: glTF metallic-roughness (+ KHR_materials_unlit, KHR_materials_emissive_strength,
// KHR_texture_transform) into the scene model, with the scene config's shading-model override;
// records which textures are sampled as colour (sRGB) and which as data.
#include <algorithm>
#include <cmath>

#include "convert_context.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

using shadergen::TextureSlot;

namespace {

void texture_ref(ConvertContext& ctx, int index, int texcoord, const std::string& p) {
  if (index < 0) return;
  if (static_cast<std::size_t>(index) >= ctx.m.textures.size()) ctx.error(p + ".index", "texture index out of range");
  if (texcoord < 0 || texcoord > 1) ctx.error(p + ".texCoord", "only TEXCOORD_0 and TEXCOORD_1 are supported");
}


glm::mat3 uv_transform(const tinygltf::ExtensionMap& ext, int& texcoord, bool& has) {
  auto it = ext.find("KHR_texture_transform");
  if (it == ext.end() || !it->second.IsObject()) return glm::mat3(1.0f);
  has = true;
  const auto& v = it->second;
  glm::vec2 offset(0.0f), scale(1.0f);
  float rotation = 0.0f;
  auto num = [](const tinygltf::Value& x) { return static_cast<float>(x.GetNumberAsDouble()); };
  if (v.Has("offset") && v.Get("offset").ArrayLen() == 2) offset = {num(v.Get("offset").Get(0)), num(v.Get("offset").Get(1))};
  if (v.Has("scale") && v.Get("scale").ArrayLen() == 2) scale = {num(v.Get("scale").Get(0)), num(v.Get("scale").Get(1))};
  if (v.Has("rotation")) rotation = num(v.Get("rotation"));
  if (v.Has("texCoord")) texcoord = v.Get("texCoord").GetNumberAsInt();
  // T * R * S as in the extension spec (column-major mat3).
  glm::mat3 t(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  glm::mat3 r(std::cos(rotation), -std::sin(rotation), 0, std::sin(rotation), std::cos(rotation), 0, 0, 0, 1);
  glm::mat3 s(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return t * r * s;
}

Material convert_material(ConvertContext& ctx, std::size_t i, std::vector<int>& texture_srgb) {
  const auto& mat = ctx.m.materials[i];
  Material out;
  out.name = mat.name.empty() ? "material" + std::to_string(i) : mat.name;
  const auto& pbr = mat.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4) out.base_color = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
  if (mat.emissiveFactor.size() == 3) out.emissive = glm::vec3(mat.emissiveFactor[0], mat.emissiveFactor[1], mat.emissiveFactor[2]);
  auto es = mat.extensions.find("KHR_materials_emissive_strength");
  if (es != mat.extensions.end() && es->second.Has("emissiveStrength")) out.emissive *= static_cast<float>(es->second.Get("emissiveStrength").GetNumberAsDouble());
  out.metallic = static_cast<float>(pbr.metallicFactor);
  out.roughness = static_cast<float>(pbr.roughnessFactor);
  out.alpha = mat.alphaMode == "MASK" ? shadergen::AlphaMode::Mask : mat.alphaMode == "BLEND" ? shadergen::AlphaMode::Blend : shadergen::AlphaMode::Opaque;
  out.alpha_cutoff = static_cast<float>(mat.alphaCutoff);
  out.double_sided = mat.doubleSided;
  out.normal_scale = static_cast<float>(mat.normalTexture.scale);
  out.occlusion_strength = static_cast<float>(mat.occlusionTexture.strength);
  out.shading = mat.extensions.count("KHR_materials_unlit") ? shadergen::ShadingModel::Unlit : shadergen::ShadingModel::PbrMetallicRoughness;
  auto ov = ctx.cfg.materials.find(out.name);
  if (ov != ctx.cfg.materials.end() && ov->second.shading) {
    // The scene-config parser accepted only the model names parse_shading_model knows.
    out.shading = parse_shading_model(*ov->second.shading).value_or(shadergen::ShadingModel::PbrMetallicRoughness);
  }
  auto slot = [&](TextureSlot s, const auto& info, bool srgb) {
    if (info.index < 0) return;
    const int k = int(s);
    out.texture[k] = info.index;
    out.texcoord[k] = info.texCoord;
    out.uv_transform[k] = uv_transform(info.extensions, out.texcoord[k], out.has_uv_transform);
    int& flag = texture_srgb[static_cast<std::size_t>(info.index)];
    const int want = srgb ? 1 : 0;
    if (flag >= 0 && flag != want) {
      // Same texture as colour and as data: keep colour (sRGB) decoding and say so.
      ctx.repair(idx("materials", i), "texture " + std::to_string(info.index) + " is used both as colour and as data; decoded as sRGB colour");
    }
    flag = std::max(flag, want);
  };
  slot(TextureSlot::BaseColor, pbr.baseColorTexture, true);
  slot(TextureSlot::MetallicRoughness, pbr.metallicRoughnessTexture, false);
  slot(TextureSlot::Normal, mat.normalTexture, false);
  slot(TextureSlot::Occlusion, mat.occlusionTexture, false);
  slot(TextureSlot::Emissive, mat.emissiveTexture, true);
  return out;
}


}  // namespace

void validate_material(ConvertContext& ctx, std::size_t i) {
  const auto& mat = ctx.m.materials[i];
  const std::string p = idx("materials", i);
  const auto& pbr = mat.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() != 4) ctx.error(p + ".pbrMetallicRoughness.baseColorFactor", "expected 4 numbers");
  for (double v : pbr.baseColorFactor) {
    if (!(v >= 0 && v <= 1)) ctx.error(p + ".pbrMetallicRoughness.baseColorFactor", "components must be in 0..1");
  }
  if (!(pbr.metallicFactor >= 0 && pbr.metallicFactor <= 1)) ctx.error(p + ".pbrMetallicRoughness.metallicFactor", "must be in 0..1");
  if (!(pbr.roughnessFactor >= 0 && pbr.roughnessFactor <= 1)) ctx.error(p + ".pbrMetallicRoughness.roughnessFactor", "must be in 0..1");
  if (mat.emissiveFactor.size() != 3) ctx.error(p + ".emissiveFactor", "expected 3 numbers");
  for (double v : mat.emissiveFactor) {
    if (!(v >= 0 && v <= 1)) ctx.error(p + ".emissiveFactor", "components must be in 0..1");
  }
  if (mat.alphaMode != "OPAQUE" && mat.alphaMode != "MASK" && mat.alphaMode != "BLEND") ctx.error(p + ".alphaMode", "unknown alpha mode \"" + mat.alphaMode + "\"");
  if (!(mat.alphaCutoff >= 0)) ctx.error(p + ".alphaCutoff", "must be >= 0");
  texture_ref(ctx, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, p + ".pbrMetallicRoughness.baseColorTexture");
  texture_ref(ctx, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, p + ".pbrMetallicRoughness.metallicRoughnessTexture");
  texture_ref(ctx, mat.normalTexture.index, mat.normalTexture.texCoord, p + ".normalTexture");
  texture_ref(ctx, mat.occlusionTexture.index, mat.occlusionTexture.texCoord, p + ".occlusionTexture");
  texture_ref(ctx, mat.emissiveTexture.index, mat.emissiveTexture.texCoord, p + ".emissiveTexture");
}


int convert_materials(ConvertContext& ctx, Scene& s, std::vector<int>& texture_srgb) {
  for (std::size_t i = 0; i < ctx.m.materials.size(); ++i) s.materials.push_back(convert_material(ctx, i, texture_srgb));
  // glTF default material for primitives without one.
  const int default_material = static_cast<int>(s.materials.size());
  Material d;
  d.name = "__default";
  d.metallic = 1.0f;
  d.roughness = 1.0f;
  s.materials.push_back(d);
  return default_material;
}

}  // namespace meter::convert
