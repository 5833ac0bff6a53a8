// The package reader: bounds-checked decoding of the format in meter/bridge/package_format.hpp.
#include "meter/engine/package_reader.hpp"

#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/merged_draws.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>

namespace meter::engine {
namespace {

class Reader {
 public:
  Reader(std::span<const std::uint8_t> d, const std::string& origin) : data_(d), origin_(origin) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw SceneError(origin_ + ": corrupt package at byte " + std::to_string(pos_) + ": " + what);
  }
  void need(std::size_t n, const char* what) {
    if (n > data_.size() - pos_) fail(std::string("truncated while reading ") + what);
  }
  template <typename T>
  T pod(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint32_t u32(const char* what) { return pod<std::uint32_t>(what); }
  std::int32_t i32(const char* what) { return pod<std::int32_t>(what); }
  float f32(const char* what) {
    float v = pod<float>(what);
    if (!std::isfinite(v)) fail(std::string("non-finite float in ") + what);
    return v;
  }
  double f64(const char* what) {
    double v = pod<double>(what);
    if (!std::isfinite(v)) fail(std::string("non-finite double in ") + what);
    return v;
  }
  bool boolean(const char* what) { return pod<std::uint8_t>(what) != 0; }
  std::uint32_t count(const char* what, std::size_t element_size) {
    std::uint32_t n = u32(what);
    if (element_size && n > (data_.size() - pos_) / element_size) fail(std::string("count too large for ") + what);
    return n;
  }
  std::string str(const char* what) {
    std::uint32_t n = count(what, 1);
    std::string s(reinterpret_cast<const char*>(data_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  template <typename T>
  std::vector<T> vec(const char* what) {
    std::uint32_t n = count(what, sizeof(T));
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), data_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
    if constexpr (std::is_floating_point_v<T>) {
      for (T x : v) {
        if (!std::isfinite(x)) fail(std::string("non-finite value in ") + what);
      }
    }
    return v;
  }
  glm::vec3 v3(const char* what) { return {f32(what), f32(what), f32(what)}; }
  glm::vec4 v4(const char* what) { return {f32(what), f32(what), f32(what), f32(what)}; }
  bool at_end() const { return pos_ == data_.size(); }

 private:
  std::span<const std::uint8_t> data_;
  std::size_t pos_ = 0;
  std::string origin_;
};

template <typename E>
E enum_in(Reader& r, int max, const char* what) {
  std::int32_t v = r.i32(what);
  if (v < 0 || v > max) r.fail(std::string("bad enum value for ") + what);
  return static_cast<E>(v);
}

bridge::MaterialFeatures read_features(Reader& r) {
  using namespace bridge;
  MaterialFeatures f;
  f.shading = enum_in<ShadingModel>(r, 4, "features.shading");
  f.alpha = enum_in<AlphaMode>(r, 2, "features.alpha");
  f.precision = enum_in<Precision>(r, 1, "features.precision");
  f.base_color_texture = r.boolean("features");
  f.metallic_roughness_texture = r.boolean("features");
  f.normal_texture = r.boolean("features");
  f.emissive_texture = r.boolean("features");
  f.occlusion_texture = r.boolean("features");
  f.texcoord1_slots = r.u32("features");
  f.texture_transform = r.boolean("features");
  f.vertex_colors = r.boolean("features");
  f.vertex_alpha = r.boolean("features");
  f.double_sided = r.boolean("features");
  f.skin_joints = r.i32("features");
  f.morph_targets = r.i32("features");
  f.morph_normals = r.boolean("features");
  f.lights.directional = r.i32("features");
  f.lights.point = r.i32("features");
  f.lights.spot = r.i32("features");
  f.lights.shadows = r.u32("features");
  f.environment_map_2d = r.boolean("features");
  f.has_tangents = r.boolean("features");
  return f;
}

ProgramEntry read_program(Reader& r) {
  using namespace bridge;
  ProgramEntry e;
  auto& p = e.program;
  p.vertex_source = r.str("program.vertex_source");
  p.fragment_source = r.str("program.fragment_source");
  for (std::uint32_t n = r.count("program.attributes", 20), i = 0; i < n; ++i) {
    AttributeInfo a;
    a.name = r.str("attribute.name");
    a.semantic = enum_in<AttributeSemantic>(r, int(AttributeSemantic::VertexAlpha), "attribute.semantic");
    a.index = r.i32("attribute.index");
    a.location = r.i32("attribute.location");
    a.components = r.i32("attribute.components");
    if (a.location < 0 || a.location > 15 || a.components < 1 || a.components > 4) r.fail("attribute location/components out of range");
    p.attributes.push_back(a);
  }
  for (std::uint32_t n = r.count("program.uniforms", 20), i = 0; i < n; ++i) {
    UniformInfo u;
    u.name = r.str("uniform.name");
    u.glsl_type = r.str("uniform.glsl_type");
    u.semantic = enum_in<UniformSemantic>(r, int(UniformSemantic::LightShadowMatrix), "uniform.semantic");
    u.index = r.i32("uniform.index");
    u.array_size = r.i32("uniform.array_size");
    if (u.array_size < 1 || u.array_size > 1024) r.fail("uniform array size out of range");
    p.uniforms.push_back(u);
  }
  for (std::uint32_t n = r.count("program.samplers", 12), i = 0; i < n; ++i) {
    SamplerInfo s;
    s.name = r.str("sampler.name");
    s.slot = enum_in<TextureSlot>(r, int(TextureSlot::ShadowMap), "sampler.slot");
    s.unit = r.i32("sampler.unit");
    if (s.unit < 0 || s.unit > 15) r.fail("sampler unit out of range");
    s.index = r.i32("sampler.index");
    if (s.slot == TextureSlot::ShadowMap ? s.index < 0 || s.index >= kMaxLights : s.index != -1)
      r.fail("sampler.index: a shadow map names a light 0.." + std::to_string(kMaxLights - 1) + ", any other sampler -1");
    p.samplers.push_back(s);
  }
  p.features = read_features(r);
  p.blend = r.boolean("program.blend");
  p.cull_back_faces = r.boolean("program.cull");
  p.optimized = r.boolean("program.optimized");
  p.uber = r.boolean("program.uber");
  auto& o = e.optimize_report;
  for (std::size_t* v : {&o.source_bytes_before, &o.source_bytes_after, &o.spirv_instructions_before,
                         &o.spirv_instructions_after, &o.uniforms_before, &o.uniforms_after,
                         &o.varyings_before, &o.varyings_after, &o.samplers_before, &o.samplers_after}) {
    *v = static_cast<std::size_t>(r.pod<std::uint64_t>("optimize report"));
  }
  for (std::uint32_t n = r.count("optimize.folded", 4), i = 0; i < n; ++i) o.folded.push_back(r.str("folded"));
  return e;
}

void check_index(Reader& r, int v, std::size_t size, bool allow_none, const char* what) {
  if ((v == -1 && allow_none) || (v >= 0 && static_cast<std::size_t>(v) < size)) return;
  r.fail(std::string(what) + " index " + std::to_string(v) + " out of range (" + std::to_string(size) + ")");
}

// The integrity table (since version 4), checked against the scene it belongs to so the checks
// never index out of range: binding indices, rects inside the frame, mask sizes, sample order.
bridge::IntegrityTable read_integrity(Reader& r) {
  using namespace bridge;
  IntegrityTable t;
  t.width = r.i32("integrity.width"), t.height = r.i32("integrity.height");
  const std::uint32_t n = r.count("integrity.regions", 40);
  if (n > 0 && (t.width <= 0 || t.height <= 0)) r.fail("integrity table without a frame size");
  for (std::uint32_t i = 0; i < n; ++i) {
    SafetyRegion g;
    g.name = r.str("region.name");
    g.kind = enum_in<SafetyKind>(r, 2, "region.kind");
    g.signal = r.str("region.signal");
    g.bindings = r.vec<int>("region.bindings");  // checked against the config once it is parsed
    g.node = r.str("region.node");
    for (std::uint32_t m = r.count("region.materials", 4), k = 0; k < m; ++k) g.materials.push_back(r.str("region.material"));
    g.rect = {r.i32("region.rect"), r.i32("region.rect"), r.i32("region.rect"), r.i32("region.rect")};
    // The far edges in 64 bits: a stored x near INT_MAX plus a width would overflow an int.
    if (g.rect.empty() || g.rect.x < 0 || g.rect.y < 0 ||
        std::int64_t{g.rect.x} + g.rect.width > t.width || std::int64_t{g.rect.y} + g.rect.height > t.height) {
      r.fail("region " + g.name + ": rect outside the integrity table's frame");
    }
    g.telltale.mask = r.vec<std::uint8_t>("telltale.mask");
    for (std::uint32_t m = r.count("telltale.looks", 26), k = 0; k < m; ++k) {
      TelltaleLook l;
      l.name = r.str("look.name");
      l.lit = r.boolean("look.lit");
      for (auto& c : l.mean) c = r.f64("look.mean");
      g.telltale.looks.push_back(std::move(l));
    }
    g.telltale.tolerance = r.f64("telltale.tolerance");
    auto& nd = g.needle;
    nd.animation = r.str("needle.animation");
    nd.pivot_x = r.f64("needle.pivot"), nd.pivot_y = r.f64("needle.pivot");
    nd.r_min = r.f64("needle.r_min"), nd.r_max = r.f64("needle.r_max");
    for (int& c : nd.color_min) c = r.i32("needle.color_min");
    for (int& c : nd.color_max) c = r.i32("needle.color_max");
    nd.min_pixels = r.i32("needle.min_pixels");
    for (std::uint32_t m = r.count("needle.samples", 24), k = 0; k < m; ++k) {
      NeedleSample s;
      s.time = r.f64("sample.time"), s.value = r.f64("sample.value"), s.angle_deg = r.f64("sample.angle");
      if (!nd.samples.empty() && s.time <= nd.samples.back().time) r.fail("region " + g.name + ": needle samples not in increasing time");
      nd.samples.push_back(s);
    }
    nd.tolerance_deg = r.f64("needle.tolerance");
    nd.sector_center_deg = r.f64("needle.sector"), nd.sector_half_deg = r.f64("needle.sector");
    auto& o = g.readout;
    o.anchor_x = r.i32("readout.anchor"), o.baseline_y = r.i32("readout.baseline");
    o.size_px = r.i32("readout.size_px");
    o.align = enum_in<TextAlign>(r, 2, "readout.align");
    o.format = r.str("readout.format");
    o.tolerance_pixels = r.i32("readout.tolerance");
    const bool telltale_ok = g.telltale.mask.size() == std::size_t(g.rect.width) * std::size_t(g.rect.height) &&
                             g.telltale.looks.size() >= 2;
    if (g.kind == SafetyKind::Telltale && !telltale_ok) r.fail("region " + g.name + ": telltale mask or looks incomplete");
    if (g.kind == SafetyKind::Needle && (nd.samples.size() < 2 || nd.r_min >= nd.r_max || g.bindings.empty())) {
      r.fail("region " + g.name + ": needle model incomplete");
    }
    if (g.kind == SafetyKind::Readout && g.bindings.empty()) r.fail("region " + g.name + ": readout without its binding");
    t.regions.push_back(std::move(g));
  }
  return t;
}

// The draw levels (since version 5). Each LOD level's indices are checked against its primitive;
// the draws' references against the scene once the draws are read (check_draw_levels).
void read_levels(Reader& r, Scene& s) {
  for (std::size_t mi = 0; mi < s.meshes.size(); ++mi)
    for (std::size_t pi = 0; pi < s.meshes[mi].primitives.size(); ++pi) {
      Primitive& p = s.meshes[mi].primitives[pi];
      const std::string at = "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "].lods";
      for (std::uint32_t n = r.count("primitive.lods", 12), k = 0; k < n; ++k) {
        LodLevel l;
        l.error = r.f32("lod.error");
        l.triangle_fraction = r.f32("lod.triangle_fraction");
        l.indices = r.vec<std::uint32_t>("lod.indices");
        const std::string lk = at + "[" + std::to_string(k) + "]";
        if (l.error < 0.0f) r.fail(lk + ".error: negative");
        if (!(l.triangle_fraction > 0.0f && l.triangle_fraction < 1.0f)) r.fail(lk + ".triangle_fraction: expected a value in (0, 1)");
        if (l.indices.empty() || l.indices.size() % 3 != 0) r.fail(lk + ".indices: expected whole triangles");
        for (auto idx : l.indices)
          if (idx >= p.vertex_count) r.fail(lk + ".indices: index " + std::to_string(idx) + " out of range of the " + std::to_string(p.vertex_count) + " vertices");
        p.lods.push_back(std::move(l));
      }
    }
  for (std::uint32_t n = r.count("draw_levels", 9), i = 0; i < n; ++i) {
    DrawLevels d;
    d.safety = r.boolean("draw_levels.safety");
    d.lods = r.i32("draw_levels.lods");
    for (std::uint32_t ns = r.count("draw_levels.shadings", 28), k = 0; k < ns; ++k) {
      ShadingLevel l;
      l.shading = enum_in<bridge::ShadingModel>(r, 4, "shading_level.shading");
      l.program = r.i32("shading_level.program");
      l.specular_color = r.v3("shading_level.specular_color");
      l.shininess = r.f32("shading_level.shininess");
      l.base_scale = r.f32("shading_level.base_scale");
      d.shadings.push_back(l);
    }
    s.draw_levels.push_back(std::move(d));
  }
}

}  // namespace

Scene deserialize_scene(std::span<const std::uint8_t> bytes, const std::string& origin) {
  constexpr std::size_t kHeader = kPackageHeaderSize;
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kPackageMagic, 8) != 0) {
    throw SceneError(origin + ": not a meter scene package (bad magic; expected \"METERSCN\" — convert the "
                     "glTF with meter-convert first)");
  }
  if (bytes.size() < kHeader) throw SceneError(origin + ": truncated package header");
  Reader h(bytes.first(kHeader), origin);
  for (int i = 0; i < 8; ++i) h.pod<char>("magic");
  std::uint32_t version = h.u32("version");
  if (version != kPackageVersion) {
    throw SceneError(origin + ": scene package format version " + std::to_string(version) +
                     " is not supported by this build (it reads version " + std::to_string(kPackageVersion) +
                     "); re-run meter-convert on the source glTF");
  }
  h.u32("reserved");
  auto size = h.pod<std::uint64_t>("payload size");
  auto hash = h.pod<std::uint64_t>("payload hash");
  if (size != bytes.size() - kHeader) {
    throw SceneError(origin + ": package payload is " + std::to_string(bytes.size() - kHeader) +
                     " bytes but the header says " + std::to_string(size) + " (truncated or padded file)");
  }
  auto payload = bytes.subspan(kHeader);
  if (package_checksum(payload) != hash) throw SceneError(origin + ": package checksum mismatch (file corrupted)");

  Reader r(payload, origin);
  Scene s;
  s.source_name = r.str("source name");
  for (std::uint32_t n = r.count("nodes", 60), i = 0; i < n; ++i) {
    Node nd;
    nd.name = r.str("node.name");
    nd.parent = r.i32("node.parent");
    nd.children = r.vec<int>("node.children");
    nd.translation = r.v3("node.translation");
    glm::vec4 q = r.v4("node.rotation");
    nd.rotation = glm::quat(q.w, q.x, q.y, q.z);
    nd.scale = r.v3("node.scale");
    nd.mesh = r.i32("node.mesh");
    nd.camera = r.i32("node.camera");
    nd.light = r.i32("node.light");
    nd.skin = r.i32("node.skin");
    nd.weights = r.vec<float>("node.weights");
    s.nodes.push_back(std::move(nd));
  }
  s.roots = r.vec<int>("roots");
  for (std::uint32_t n = r.count("meshes", 8), i = 0; i < n; ++i) {
    Mesh m;
    m.name = r.str("mesh.name");
    m.weights = r.vec<float>("mesh.weights");
    for (std::uint32_t np = r.count("primitives", 40), k = 0; k < np; ++k) {
      Primitive p;
      p.material = r.i32("primitive.material");
      p.vertex_count = r.u32("primitive.vertex_count");
      p.stride = r.i32("primitive.stride");
      p.morph_targets = r.i32("primitive.morph_targets");
      for (std::uint32_t na = r.count("layout", 16), a = 0; a < na; ++a) {
        VertexAttribute va;
        va.semantic = enum_in<bridge::AttributeSemantic>(r, int(bridge::AttributeSemantic::VertexAlpha), "layout.semantic");
        va.index = r.i32("layout.index");
        va.components = r.i32("layout.components");
        va.offset = r.i32("layout.offset");
        if (va.components < 1 || va.components > 4 || va.offset < 0 || va.offset + va.components > p.stride) {
          r.fail("vertex attribute outside the vertex record");
        }
        p.layout.push_back(va);
      }
      p.vertices = r.vec<float>("primitive.vertices");
      p.indices = r.vec<std::uint32_t>("primitive.indices");
      if (p.stride <= 0 || p.vertices.size() != std::size_t(p.vertex_count) * std::size_t(p.stride)) {
        r.fail("vertex data size does not match vertex_count * stride");
      }
      for (auto idx : p.indices) {
        if (idx >= p.vertex_count) r.fail("index out of range of the vertex data");
      }
      p.bounds_min = r.v3("primitive.bounds");
      p.bounds_max = r.v3("primitive.bounds");
      m.primitives.push_back(std::move(p));
    }
    s.meshes.push_back(std::move(m));
  }
  for (std::uint32_t n = r.count("materials", 40), i = 0; i < n; ++i) {
    Material m;
    m.name = r.str("material.name");
    m.shading = enum_in<bridge::ShadingModel>(r, 4, "material.shading");
    m.alpha = enum_in<bridge::AlphaMode>(r, 2, "material.alpha");
    m.double_sided = r.boolean("material.double_sided");
    m.base_color = r.v4("material.base_color");
    m.emissive = r.v3("material.emissive");
    m.metallic = r.f32("material");
    m.roughness = r.f32("material");
    m.normal_scale = r.f32("material");
    m.occlusion_strength = r.f32("material");
    m.alpha_cutoff = r.f32("material");
    m.specular_color = r.v3("material");
    m.shininess = r.f32("material");
    for (int t = 0; t < 6; ++t) {
      m.texture[t] = r.i32("material.texture");
      m.texcoord[t] = r.i32("material.texcoord");
      for (int c = 0; c < 3; ++c) m.uv_transform[t][c] = r.v3("material.uv_transform");
    }
    m.has_uv_transform = r.boolean("material");
    s.materials.push_back(std::move(m));
  }
  for (std::uint32_t n = r.count("textures", 20), i = 0; i < n; ++i) {
    Texture t;
    t.name = r.str("texture.name");
    t.width = r.i32("texture.width");
    t.height = r.i32("texture.height");
    t.rgba = r.vec<std::uint8_t>("texture.rgba");
    if (t.width <= 0 || t.height <= 0 || t.width > 16384 || t.height > 16384 ||
        t.rgba.size() != std::size_t(t.width) * std::size_t(t.height) * 4) {
      r.fail("texture size does not match its pixel data");
    }
    t.srgb = r.boolean("texture.srgb");
    t.min_filter = r.i32("texture");
    t.mag_filter = r.i32("texture");
    t.wrap_s = r.i32("texture");
    t.wrap_t = r.i32("texture");
    s.textures.push_back(std::move(t));
  }
  for (std::uint32_t n = r.count("cameras", 20), i = 0; i < n; ++i) {
    Camera c;
    c.name = r.str("camera.name");
    c.perspective = r.boolean("camera");
    c.yfov = r.f32("camera"), c.znear = r.f32("camera"), c.zfar = r.f32("camera");
    c.xmag = r.f32("camera"), c.ymag = r.f32("camera");
    s.cameras.push_back(std::move(c));
  }
  for (std::uint32_t n = r.count("lights", 20), i = 0; i < n; ++i) {
    Light l;
    l.name = r.str("light.name");
    l.type = enum_in<LightType>(r, 2, "light.type");
    l.color = r.v3("light.color");
    l.intensity = r.f32("light"), l.range = r.f32("light"), l.inner_cone = r.f32("light"), l.outer_cone = r.f32("light");
    l.cast_shadow = r.boolean("light");
    s.lights.push_back(std::move(l));
  }
  for (std::uint32_t n = r.count("skins", 8), i = 0; i < n; ++i) {
    Skin k;
    k.name = r.str("skin.name");
    k.joints = r.vec<int>("skin.joints");
    for (std::uint32_t nm = r.count("skin.inverse_bind", 64), j = 0; j < nm; ++j) {
      glm::mat4 m;
      for (int c = 0; c < 4; ++c) m[c] = r.v4("skin.inverse_bind");
      k.inverse_bind.push_back(m);
    }
    if (k.inverse_bind.size() != k.joints.size()) r.fail("skin has a different number of joints and matrices");
    s.skins.push_back(std::move(k));
  }
  for (std::uint32_t n = r.count("animations", 20), i = 0; i < n; ++i) {
    Animation a;
    a.name = r.str("animation.name");
    a.start = r.f32("animation.start");
    a.end = r.f32("animation.end");
    for (std::uint32_t ns = r.count("samplers", 16), k = 0; k < ns; ++k) {
      AnimSampler sm;
      sm.interpolation = enum_in<Interpolation>(r, 2, "sampler.interpolation");
      sm.components = r.i32("sampler.components");
      sm.input = r.vec<float>("sampler.input");
      sm.output = r.vec<float>("sampler.output");
      std::size_t per_key = std::size_t(sm.components) * (sm.interpolation == Interpolation::CubicSpline ? 3 : 1);
      if (sm.components < 1 || sm.components > 256 || sm.input.empty() || sm.output.size() != sm.input.size() * per_key) {
        r.fail("animation sampler output size does not match its keys");
      }
      a.samplers.push_back(std::move(sm));
    }
    for (std::uint32_t nc = r.count("channels", 12), k = 0; k < nc; ++k) {
      AnimChannel ch;
      ch.sampler = r.i32("channel.sampler");
      ch.node = r.i32("channel.node");
      ch.path = enum_in<TargetPath>(r, 3, "channel.path");
      a.channels.push_back(ch);
    }
    s.animations.push_back(std::move(a));
  }
  for (std::uint32_t n = r.count("programs", 40), i = 0; i < n; ++i) s.programs.push_back(read_program(r));
  for (std::uint32_t n = r.count("draws", 16), i = 0; i < n; ++i) {
    DrawItem d;
    d.node = r.i32("draw.node"), d.mesh = r.i32("draw.mesh"), d.primitive = r.i32("draw.primitive"), d.program = r.i32("draw.program");
    s.draws.push_back(d);
  }
  for (std::uint32_t n = r.count("groups", 8), i = 0; i < n; ++i) {
    MergedGroup g;
    g.name = r.str("group.name");
    g.draws = r.vec<int>("group.draws");
    s.groups.push_back(std::move(g));
  }
  {
    EnvironmentProbe& probe = s.environment.probe;
    probe.face_size = r.i32("environment.probe.face_size");
    probe.levels = r.i32("environment.probe.levels");
    probe.rgb = r.vec<std::uint8_t>("environment.probe.rgb");
    const bool none = probe.face_size == 0 && probe.levels == 0 && probe.rgb.empty();
    const bool sized = probe.face_size >= 8 && probe.face_size <= 4096 && (probe.face_size & (probe.face_size - 1)) == 0 &&
                       probe.levels == EnvironmentProbe::levels_for(probe.face_size);
    if (!none && !sized)
      r.fail("environment.probe: face size " + std::to_string(probe.face_size) + " with " + std::to_string(probe.levels) +
             " levels; expected a power of two in 8..4096 and log2(face size) - 2 levels");
    if (!none && probe.rgb.size() != EnvironmentProbe::byte_size(probe.face_size, probe.levels))
      r.fail("environment.probe: " + std::to_string(probe.rgb.size()) + " bytes of texels; expected " +
             std::to_string(EnvironmentProbe::byte_size(probe.face_size, probe.levels)));
  }
  s.environment.strength = r.f32("environment.strength");
  if (s.environment.strength < 0.0f) r.fail("negative environment.strength");
  for (auto& e : s.environment.irradiance) e = r.v3("environment.irradiance");
  std::string config_json = r.str("config");
  s.integrity = read_integrity(r);
  read_levels(r, s);
  if (!r.at_end()) r.fail("trailing bytes after the last section");

  // Cross-references: a package that passed the checksum but was written by a buggy converter
  // must still never index out of range at runtime.
  const auto nn = s.nodes.size();
  for (const auto& nd : s.nodes) {
    check_index(r, nd.parent, nn, true, "node.parent");
    for (int c : nd.children) check_index(r, c, nn, false, "node.children");
    check_index(r, nd.mesh, s.meshes.size(), true, "node.mesh");
    check_index(r, nd.camera, s.cameras.size(), true, "node.camera");
    check_index(r, nd.light, s.lights.size(), true, "node.light");
    check_index(r, nd.skin, s.skins.size(), true, "node.skin");
  }
  for (int root : s.roots) check_index(r, root, nn, false, "roots");
  for (const auto& m : s.meshes) {
    for (const auto& p : m.primitives) check_index(r, p.material, s.materials.size(), false, "primitive.material");
  }
  for (const auto& m : s.materials) {
    for (int t : m.texture) check_index(r, t, s.textures.size(), true, "material.texture");
  }
  for (const auto& k : s.skins) {
    for (int j : k.joints) check_index(r, j, nn, false, "skin.joints");
  }
  for (const auto& a : s.animations) {
    for (const auto& ch : a.channels) {
      check_index(r, ch.sampler, a.samplers.size(), false, "channel.sampler");
      check_index(r, ch.node, nn, false, "channel.node");
    }
  }
  for (const auto& d : s.draws) {
    check_index(r, d.node, nn, false, "draw.node");
    check_index(r, d.mesh, s.meshes.size(), false, "draw.mesh");
    check_index(r, d.primitive, s.meshes[std::size_t(d.mesh)].primitives.size(), false, "draw.primitive");
    check_index(r, d.program, s.programs.size(), false, "draw.program");
  }
  if (const std::string why = check_groups(s); !why.empty()) r.fail(why);
  if (const std::string why = check_draw_levels(s); !why.empty()) r.fail(why);
  try {
    s.config = parse_scene_config(config_json, origin + " (embedded scene config)");
  } catch (const std::invalid_argument& e) {
    throw SceneError(e.what());
  }
  s.ambient = glm::vec3(s.config.ambient[0], s.config.ambient[1], s.config.ambient[2]);
  for (const auto& g : s.integrity.regions) {
    for (int b : g.bindings) {
      if (b < 0 || std::size_t(b) >= s.config.bindings.size()) {
        throw SceneError(origin + ": corrupt package: integrity region " + g.name + " names binding " + std::to_string(b) +
                         " of " + std::to_string(s.config.bindings.size()));
      }
    }
  }
  return s;
}

Scene read_package(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open scene package");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return deserialize_scene(bytes, path);
}

}  // namespace meter::engine
