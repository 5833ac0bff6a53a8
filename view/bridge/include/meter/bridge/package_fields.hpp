// The field list of every record the scene package holds: ONE list per record, in package order,
// that drives the package writer (meter/convert), the package reader (meter/engine), the record
// dump (meter-package dump) and the program cache key. `fields(record, visit)` calls
// `visit(name, member)` for each stored member, in order; `record` may be const (writer, dump) or
// not (reader). A member that is itself a record (or a list / array of records) is visited by its
// own list. Runtime-only members (Texture::max_anisotropy, Scene::ambient, the parsed config) are
// not listed: they are not stored.
//
// Adding a member to a record = one line here (plus the member); a material term is added in
// material_feature_fields.hpp. How each kind of value is encoded is bridge/package_format.hpp's.
#pragma once


#include "meter/bridge/program_fields.hpp"
#include "meter/bridge/scene.hpp"

namespace meter::bridge {

template <> inline constexpr int enum_last<Interpolation> = int(Interpolation::CubicSpline);
template <> inline constexpr int enum_last<TargetPath> = int(TargetPath::Weights);
template <> inline constexpr int enum_last<LightType> = int(LightType::Spot);
template <> inline constexpr int enum_last<SafetyKind> = int(SafetyKind::Readout);
template <> inline constexpr int enum_last<TextAlign> = int(TextAlign::Right);

// --- geometry -------------------------------------------------------------------------------------

template <record_of<Node> R, class V>
void fields(R& n, V&& v) {
  v("name", n.name), v("parent", n.parent), v("children", n.children);
  v("translation", n.translation), v("rotation", n.rotation), v("scale", n.scale);
  v("mesh", n.mesh), v("camera", n.camera), v("light", n.light), v("skin", n.skin);
  v("weights", n.weights);
}

template <record_of<VertexAttribute> R, class V>
void fields(R& a, V&& v) {
  v("semantic", a.semantic), v("index", a.index), v("components", a.components), v("offset", a.offset);
}

template <record_of<LodLevel> R, class V>
void fields(R& l, V&& v) {
  v("error", l.error), v("triangle_fraction", l.triangle_fraction), v("indices", l.indices);
}

template <record_of<Primitive> R, class V>
void fields(R& p, V&& v) {
  v("material", p.material), v("vertex_count", p.vertex_count), v("stride", p.stride);
  v("morph_targets", p.morph_targets), v("layout", p.layout), v("vertices", p.vertices);
  v("indices", p.indices), v("bounds_min", p.bounds_min), v("bounds_max", p.bounds_max);
  v("lods", p.lods);
}

template <record_of<Mesh> R, class V>
void fields(R& m, V&& v) {
  v("name", m.name), v("weights", m.weights), v("primitives", m.primitives);
}

// --- look -----------------------------------------------------------------------------------------

template <record_of<Material> R, class V>
void fields(R& m, V&& v) {
  v("name", m.name), v("shading", m.shading), v("alpha", m.alpha), v("double_sided", m.double_sided);
  v("base_color", m.base_color), v("emissive", m.emissive), v("metallic", m.metallic);
  v("roughness", m.roughness), v("normal_scale", m.normal_scale);
  v("occlusion_strength", m.occlusion_strength), v("alpha_cutoff", m.alpha_cutoff);
  v("specular_color", m.specular_color), v("shininess", m.shininess), v("texture", m.texture);
  v("texcoord", m.texcoord), v("uv_transform", m.uv_transform), v("has_uv_transform", m.has_uv_transform);
}

template <record_of<Texture> R, class V>
void fields(R& t, V&& v) {
  v("name", t.name), v("width", t.width), v("height", t.height), v("rgba", t.rgba), v("srgb", t.srgb);
  v("min_filter", t.min_filter), v("mag_filter", t.mag_filter), v("wrap_s", t.wrap_s), v("wrap_t", t.wrap_t);
}

template <record_of<Camera> R, class V>
void fields(R& c, V&& v) {
  v("name", c.name), v("perspective", c.perspective), v("yfov", c.yfov), v("znear", c.znear);
  v("zfar", c.zfar), v("xmag", c.xmag), v("ymag", c.ymag);
}

template <record_of<Light> R, class V>
void fields(R& l, V&& v) {
  v("name", l.name), v("type", l.type), v("color", l.color), v("intensity", l.intensity);
  v("range", l.range), v("inner_cone", l.inner_cone), v("outer_cone", l.outer_cone);
  v("cast_shadow", l.cast_shadow);
}

template <record_of<EnvironmentProbe> R, class V>
void fields(R& p, V&& v) {
  v("face_size", p.face_size), v("levels", p.levels), v("rgb", p.rgb);
}

template <record_of<Environment> R, class V>
void fields(R& e, V&& v) {
  v("probe", e.probe), v("strength", e.strength), v("irradiance", e.irradiance);
}

// --- motion ---------------------------------------------------------------------------------------

template <record_of<Skin> R, class V>
void fields(R& k, V&& v) {
  v("name", k.name), v("joints", k.joints), v("inverse_bind", k.inverse_bind);
}

template <record_of<AnimSampler> R, class V>
void fields(R& s, V&& v) {
  v("interpolation", s.interpolation), v("components", s.components), v("input", s.input), v("output", s.output);
}

template <record_of<AnimChannel> R, class V>
void fields(R& c, V&& v) {
  v("sampler", c.sampler), v("node", c.node), v("path", c.path);
}

template <record_of<Animation> R, class V>
void fields(R& a, V&& v) {
  v("name", a.name), v("start", a.start), v("end", a.end), v("samplers", a.samplers), v("channels", a.channels);
}

// --- programs and draws ---------------------------------------------------------------------------

template <record_of<ProgramEntry> R, class V>
void fields(R& e, V&& v) {
  v("program", e.program), v("optimize_report", e.optimize_report);
}

template <record_of<DrawItem> R, class V>
void fields(R& d, V&& v) {
  v("node", d.node), v("mesh", d.mesh), v("primitive", d.primitive), v("program", d.program);
}

template <record_of<MergedGroup> R, class V>
void fields(R& g, V&& v) {
  v("name", g.name), v("draws", g.draws);
}

template <record_of<ShadingLevel> R, class V>
void fields(R& l, V&& v) {
  v("shading", l.shading), v("program", l.program), v("specular_color", l.specular_color);
  v("shininess", l.shininess), v("base_scale", l.base_scale);
}

template <record_of<DrawLevels> R, class V>
void fields(R& d, V&& v) {
  v("safety", d.safety), v("lods", d.lods), v("shadings", d.shadings);
}

// --- integrity (integrity.hpp) --------------------------------------------------------------------

template <record_of<PixelRect> R, class V>
void fields(R& r, V&& v) {
  v("x", r.x), v("y", r.y), v("width", r.width), v("height", r.height);
}

template <record_of<TelltaleLook> R, class V>
void fields(R& l, V&& v) {
  v("name", l.name), v("lit", l.lit), v("mean", l.mean);
}

template <record_of<TelltaleModel> R, class V>
void fields(R& t, V&& v) {
  v("mask", t.mask), v("looks", t.looks), v("tolerance", t.tolerance);
}

template <record_of<NeedleSample> R, class V>
void fields(R& s, V&& v) {
  v("time", s.time), v("value", s.value), v("angle_deg", s.angle_deg);
}

template <record_of<NeedleModel> R, class V>
void fields(R& n, V&& v) {
  v("animation", n.animation), v("pivot_x", n.pivot_x), v("pivot_y", n.pivot_y), v("r_min", n.r_min);
  v("r_max", n.r_max), v("color_min", n.color_min), v("color_max", n.color_max);
  v("min_pixels", n.min_pixels), v("samples", n.samples), v("tolerance_deg", n.tolerance_deg);
  v("sector_center_deg", n.sector_center_deg), v("sector_half_deg", n.sector_half_deg);
}

template <record_of<ReadoutModel> R, class V>
void fields(R& o, V&& v) {
  v("anchor_x", o.anchor_x), v("baseline_y", o.baseline_y), v("size_px", o.size_px), v("align", o.align);
  v("format", o.format), v("tolerance_pixels", o.tolerance_pixels);
}

template <record_of<SafetyRegion> R, class V>
void fields(R& g, V&& v) {
  v("name", g.name), v("kind", g.kind), v("signal", g.signal), v("bindings", g.bindings);
  v("node", g.node), v("materials", g.materials), v("rect", g.rect), v("telltale", g.telltale);
  v("needle", g.needle), v("readout", g.readout);
}

template <record_of<IntegrityTable> R, class V>
void fields(R& t, V&& v) {
  v("width", t.width), v("height", t.height), v("regions", t.regions);
}

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
}

inline const char* field_name(const SceneSection& s) { return s.name; }

}  // namespace meter::bridge
