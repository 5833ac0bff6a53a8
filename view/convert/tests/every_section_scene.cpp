// The every-section scene (every_section_scene.hpp).
#include "every_section_scene.hpp"

#include "meter/convert/scene_font.hpp"
#include "test_scenes.hpp"

namespace meter::convert::test {

using engine::test::quad_primitive;

Scene every_section() {
  Scene s;
  s.source_name = "hand-built";
  Node root;
  root.name = "Root";
  root.children = {1};
  root.translation = {1, 2, 3};
  root.rotation = glm::quat(0.5f, 0.5f, 0.5f, 0.5f);
  root.scale = {2, 2, 2};
  Node quad;
  quad.name = "Quad";
  quad.parent = 0;
  quad.mesh = 0;
  quad.light = 0;
  quad.camera = 0;
  quad.skin = 0;
  quad.weights = {0.25f};
  s.nodes = {root, quad};
  s.roots = {0};
  Mesh m;
  m.name = "QuadMesh";
  m.weights = {0.25f};
  m.primitives.push_back(quad_primitive(0, 2.0f));
  s.meshes.push_back(m);
  Material mat;
  mat.name = "Paint";
  mat.alpha = bridge::AlphaMode::Blend;
  mat.base_color = {0.1f, 0.2f, 0.3f, 0.4f};
  mat.texture[0] = 0;
  mat.uv_transform[0] = glm::mat3(2.0f);
  mat.has_uv_transform = true;
  s.materials.push_back(mat);
  Texture t;
  t.name = "Checker";
  t.width = t.height = 2;
  t.rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 0};
  t.srgb = true;
  s.textures.push_back(t);
  s.cameras.push_back(engine::test::perspective_camera("Cam", 0.7f));
  Light l;
  l.name = "Sun";
  l.type = LightType::Spot;
  l.intensity = 3.0f;
  l.cast_shadow = true;
  s.lights.push_back(l);
  Skin k;
  k.name = "Rig";
  k.joints = {0};
  k.inverse_bind = {glm::mat4(1.0f)};
  s.skins.push_back(k);
  Animation a;
  a.name = "Spin";
  a.samplers.push_back({Interpolation::Step, 3, {0.0f, 1.0f}, {0, 0, 0, 1, 1, 1}});
  a.channels.push_back({0, 1, TargetPath::Translation});
  a.end = 1.0f;
  s.animations.push_back(a);
  ProgramEntry pe;
  pe.program.vertex_source = "void main() {}";
  pe.program.fragment_source = "void main() { }";
  pe.program.attributes.push_back({"a_position", AttributeSemantic::Position, -1, 0, 3});
  pe.program.attributes.push_back({"a_vertex_alpha", AttributeSemantic::VertexAlpha, -1, 1, 1});
  pe.program.blend = true;
  // Shadows (version 6): the spot's map sampled on unit 1.
  pe.program.features.lights.spot = 1;
  pe.program.features.lights.shadows = 1;
  pe.program.samplers.push_back({"u_light0_shadow_map", bridge::TextureSlot::ShadowMap, 1, 0});
  pe.optimize_report.spirv_instructions_before = 120;
  pe.optimize_report.folded = {"u_base_color"};
  s.programs.push_back(pe);
  // Draw levels (version 5): a cheaper shading of the draw and one LOD of its primitive.
  ProgramEntry unlit = pe;
  unlit.program.features.shading = bridge::ShadingModel::Unlit;
  unlit.program.fragment_source = "void main() { /* unlit */ }";
  s.programs.push_back(unlit);
  s.meshes[0].primitives[0].lods = {LodLevel{0.01f, 0.5f, {0, 1, 2}}};
  s.draw_levels = {DrawLevels{false, {ShadingLevel{bridge::ShadingModel::Unlit, 1, {0.04f, 0.05f, 0.06f}, 12.0f, 0.25f}}, 1}};
  s.draws = {{1, 0, 0, 0}};
  s.environment.probe.face_size = 8;
  s.environment.probe.levels = 1;
  s.environment.probe.rgb.resize(bridge::EnvironmentProbe::byte_size(8, 1));
  for (std::size_t i = 0; i < s.environment.probe.rgb.size(); ++i) s.environment.probe.rgb[i] = std::uint8_t(i * 7);
  s.environment.strength = 0.5f;
  s.environment.irradiance[2] = {0.1f, 0.2f, 0.3f};
  s.config.source_json = R"({"format": "meter-scene-config/1"})";
  s.font = read_font_file(METER_FONT_FILE);  // the reader checks that FreeType opens it
  return s;
}


}  // namespace meter::convert::test
