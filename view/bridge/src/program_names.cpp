// Human-readable names of the program vocabulary (program keys, tools, error messages).
#include "meter/bridge/program.hpp"

namespace meter::bridge {

const char* to_string(ShadingModel m) {
  switch (m) {
    case ShadingModel::Unlit: return "unlit";
    case ShadingModel::Flat: return "flat";
    case ShadingModel::Gouraud: return "gouraud";
    case ShadingModel::BlinnPhong: return "blinn-phong";
    case ShadingModel::PbrMetallicRoughness: return "pbr";
  }
  return "?";
}

const char* to_string(AlphaMode m) {
  switch (m) {
    case AlphaMode::Opaque: return "opaque";
    case AlphaMode::Mask: return "mask";
    case AlphaMode::Blend: return "blend";
  }
  return "?";
}

const char* to_string(TextureSlot s) {
  switch (s) {
    case TextureSlot::BaseColor: return "base_color";
    case TextureSlot::MetallicRoughness: return "metallic_roughness";
    case TextureSlot::Normal: return "normal";
    case TextureSlot::Emissive: return "emissive";
    case TextureSlot::Occlusion: return "occlusion";
    case TextureSlot::Environment: return "environment";
    case TextureSlot::ShadowMap: return "shadow_map";
  }
  return "?";
}

const char* to_string(UniformSemantic s) {
  switch (s) {
    case UniformSemantic::ModelMatrix: return "ModelMatrix";
    case UniformSemantic::ViewProjection: return "ViewProjection";
    case UniformSemantic::NormalMatrix: return "NormalMatrix";
    case UniformSemantic::CameraPosition: return "CameraPosition";
    case UniformSemantic::BaseColorFactor: return "BaseColorFactor";
    case UniformSemantic::EmissiveFactor: return "EmissiveFactor";
    case UniformSemantic::MetallicFactor: return "MetallicFactor";
    case UniformSemantic::RoughnessFactor: return "RoughnessFactor";
    case UniformSemantic::NormalScale: return "NormalScale";
    case UniformSemantic::OcclusionStrength: return "OcclusionStrength";
    case UniformSemantic::AlphaCutoff: return "AlphaCutoff";
    case UniformSemantic::SpecularColor: return "SpecularColor";
    case UniformSemantic::Shininess: return "Shininess";
    case UniformSemantic::AmbientLight: return "AmbientLight";
    case UniformSemantic::LightColor: return "LightColor";
    case UniformSemantic::LightIntensity: return "LightIntensity";
    case UniformSemantic::LightPosition: return "LightPosition";
    case UniformSemantic::LightDirection: return "LightDirection";
    case UniformSemantic::LightRange: return "LightRange";
    case UniformSemantic::LightInnerConeCos: return "LightInnerConeCos";
    case UniformSemantic::LightOuterConeCos: return "LightOuterConeCos";
    case UniformSemantic::JointMatrices: return "JointMatrices";
    case UniformSemantic::MorphWeights: return "MorphWeights";
    case UniformSemantic::TextureTransform: return "TextureTransform";
    case UniformSemantic::EnvironmentIntensity: return "EnvironmentIntensity";
    case UniformSemantic::EnvironmentIrradiance: return "EnvironmentIrradiance";
    case UniformSemantic::Exposure: return "Exposure";
    case UniformSemantic::UberSwitches: return "UberSwitches";
    case UniformSemantic::UberLightCounts: return "UberLightCounts";
    case UniformSemantic::LightShadowMatrix: return "LightShadowMatrix";
  }
  return "?";
}

const char* to_string(AttributeSemantic s) {
  switch (s) {
    case AttributeSemantic::Position: return "POSITION";
    case AttributeSemantic::Normal: return "NORMAL";
    case AttributeSemantic::Tangent: return "TANGENT";
    case AttributeSemantic::TexCoord0: return "TEXCOORD_0";
    case AttributeSemantic::TexCoord1: return "TEXCOORD_1";
    case AttributeSemantic::Color0: return "COLOR_0";
    case AttributeSemantic::Joints0: return "JOINTS_0";
    case AttributeSemantic::Weights0: return "WEIGHTS_0";
    case AttributeSemantic::MorphPosition: return "MORPH_POSITION";
    case AttributeSemantic::MorphNormal: return "MORPH_NORMAL";
    case AttributeSemantic::VertexAlpha: return "VERTEX_ALPHA";
  }
  return "?";
}

}  // namespace meter::bridge
