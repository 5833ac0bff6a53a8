// The field list of every record the scene package holds: ONE list per record, in package order,
// that drives the package writer (meter/convert), the package reader (meter/engine), the record
// dump (meter-package dump), each section's schema (package_schema.hpp) and the program cache key.
// `fields(record, visit)` calls `visit(name, member)` for each stored member, in order; `record`
// may be const (writer, dump) or not (reader). A member that is itself a record (or a list / array
// of records) is visited by its own list. Runtime-only members (Texture::max_anisotropy,
// Scene::ambient, the parsed config) are not listed: they are not stored.
//
// Adding a member to a record = its name in the record's line here (plus the member); a material
// term is added in material_feature_fields.hpp. How each kind of value is encoded is
// bridge/package_format.hpp's.
#pragma once

#include "meter/bridge/program_fields.hpp"
#include "meter/bridge/scene.hpp"

namespace meter::bridge {

// The largest value of the scene's stored enums (program_fields.hpp has the program's).
template <> inline constexpr int enum_last<Interpolation> = int(Interpolation::CubicSpline);
template <> inline constexpr int enum_last<TargetPath> = int(TargetPath::Weights);
template <> inline constexpr int enum_last<LightType> = int(LightType::Spot);
template <> inline constexpr int enum_last<SafetyKind> = int(SafetyKind::Readout);
template <> inline constexpr int enum_last<TextAlign> = int(TextAlign::Right);

// --- geometry -------------------------------------------------------------------------------------

METER_PACKAGE_RECORD(Node, name, parent, children, translation, rotation, scale, mesh, camera, light, skin,
                     weights)

METER_PACKAGE_RECORD(VertexAttribute, semantic, index, components, offset)

METER_PACKAGE_RECORD(LodLevel, error, triangle_fraction, indices, flat_indices)

METER_PACKAGE_RECORD(Primitive, material, vertex_count, stride, morph_targets, layout, vertices, indices,
                     bounds_min, bounds_max, lods, flat_indices)

METER_PACKAGE_RECORD(Mesh, name, weights, primitives)

// --- look -----------------------------------------------------------------------------------------

METER_PACKAGE_RECORD(Material, name, shading, alpha, double_sided, base_color, emissive, metallic,
                     roughness, normal_scale, occlusion_strength, alpha_cutoff, specular_color, shininess,
                     texture, texcoord, uv_transform, has_uv_transform)

METER_PACKAGE_RECORD(Texture, name, width, height, rgba, srgb, min_filter, mag_filter, wrap_s, wrap_t)

METER_PACKAGE_RECORD(Camera, name, perspective, yfov, znear, zfar, xmag, ymag)

METER_PACKAGE_RECORD(Light, name, type, color, intensity, range, inner_cone, outer_cone, cast_shadow)

METER_PACKAGE_RECORD(EnvironmentProbe, face_size, levels, rgb)

METER_PACKAGE_RECORD(Environment, probe, strength, irradiance)

// --- motion ---------------------------------------------------------------------------------------

METER_PACKAGE_RECORD(Skin, name, joints, inverse_bind)

METER_PACKAGE_RECORD(AnimSampler, interpolation, components, input, output)

METER_PACKAGE_RECORD(AnimChannel, sampler, node, path)

METER_PACKAGE_RECORD(Animation, name, start, end, samplers, channels)

// --- programs and draws ---------------------------------------------------------------------------

METER_PACKAGE_RECORD(ProgramEntry, program, optimize_report)

METER_PACKAGE_RECORD(DrawItem, node, mesh, primitive, program)

METER_PACKAGE_RECORD(MergedGroup, name, draws)

METER_PACKAGE_RECORD(ShadingLevel, shading, program, specular_color, shininess, base_scale)

METER_PACKAGE_RECORD(DrawLevels, safety, lods, shadings)

// --- integrity (integrity.hpp) --------------------------------------------------------------------

METER_PACKAGE_RECORD(PixelRect, x, y, width, height)

METER_PACKAGE_RECORD(TelltaleLook, name, lit, mean)

METER_PACKAGE_RECORD(TelltaleModel, mask, looks, tolerance)

METER_PACKAGE_RECORD(NeedleSample, time, value, angle_deg)

METER_PACKAGE_RECORD(NeedleModel, animation, pivot_x, pivot_y, r_min, r_max, color_min, color_max,
                     min_pixels, samples, tolerance_deg, sector_center_deg, sector_half_deg)

METER_PACKAGE_RECORD(ReadoutModel, anchor_x, baseline_y, size_px, align, format, tolerance_pixels)

METER_PACKAGE_RECORD(SafetyRegion, name, kind, signal, bindings, node, materials, rect, telltale, needle,
                     readout)

METER_PACKAGE_RECORD(IntegrityTable, width, height, regions)

// --- text -----------------------------------------------------------------------------------------

METER_PACKAGE_RECORD(SceneFont, name, data)

// --- the scene: its stored members, each a section of the package ---------------------------------

// One top-level section: its four-character chunk tag, its name, and whether a package must have it.
struct SceneSection {
  const char* tag;
  const char* name;
  bool required;
};

// The sections in package order. The config is stored as its JSON text (the reader parses it).
template <record_of<Scene> S, class V>
void fields(S& s, V&& v) {
  v(SceneSection{"SRCN", "source_name", true}, s.source_name);
  v(SceneSection{"NODE", "nodes", true}, s.nodes);
  v(SceneSection{"ROOT", "roots", true}, s.roots);
  v(SceneSection{"MESH", "meshes", true}, s.meshes);
  v(SceneSection{"MATL", "materials", true}, s.materials);
  v(SceneSection{"TEXR", "textures", true}, s.textures);
  v(SceneSection{"CAMR", "cameras", true}, s.cameras);
  v(SceneSection{"LGHT", "lights", true}, s.lights);
  v(SceneSection{"SKIN", "skins", true}, s.skins);
  v(SceneSection{"ANIM", "animations", true}, s.animations);
  v(SceneSection{"PROG", "programs", true}, s.programs);
  v(SceneSection{"DRAW", "draws", true}, s.draws);
  v(SceneSection{"GRUP", "groups", false}, s.groups);
  v(SceneSection{"ENVR", "environment", false}, s.environment);
  v(SceneSection{"CONF", "config", true}, s.config.source_json);
  v(SceneSection{"INTG", "integrity", false}, s.integrity);
  v(SceneSection{"LEVL", "draw_levels", false}, s.draw_levels);
  v(SceneSection{"FONT", "font", false}, s.font);
}

inline const char* field_name(const SceneSection& s) { return s.name; }

// --- runs of floats -------------------------------------------------------------------------------

template <> inline constexpr bool is_float_run<glm::vec3> = true;
template <> inline constexpr bool is_float_run<glm::vec4> = true;
template <> inline constexpr bool is_float_run<glm::quat> = true;
template <> inline constexpr bool is_float_run<glm::mat3> = true;
template <> inline constexpr bool is_float_run<glm::mat4> = true;

// Each float of a vector, quaternion (x, y, z, w) or matrix (column by column), in package order.
template <class T, class F>
void for_each_float(T& v, F&& f) {
  using U = std::remove_const_t<T>;
  if constexpr (std::is_same_v<U, glm::quat>) {
    f(v.x), f(v.y), f(v.z), f(v.w);
  } else if constexpr (std::is_same_v<U, glm::mat3> || std::is_same_v<U, glm::mat4>) {
    for (int c = 0; c < U::length(); ++c) for_each_float(v[c], f);
  } else {
    for (int i = 0; i < U::length(); ++i) f(v[i]);
  }
}

}  // namespace meter::bridge
