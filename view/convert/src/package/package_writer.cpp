// The package writer: the Scene encoded as bridge/package_format.hpp defines it.
#include "meter/convert/package_writer.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>

#include "meter/bridge/package_format.hpp"

namespace meter::convert {
namespace {

class Writer {
 public:
  std::vector<std::uint8_t> buf;
  template <typename T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    buf.insert(buf.end(), p, p + sizeof(T));
  }
  void u32(std::uint32_t v) { pod(v); }
  void i32(std::int32_t v) { pod(v); }
  void f32(float v) { pod(v); }
  void f64(double v) { pod(v); }
  void boolean(bool v) { pod(static_cast<std::uint8_t>(v ? 1 : 0)); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    buf.insert(buf.end(), s.begin(), s.end());
  }
  template <typename T>
  void vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    u32(static_cast<std::uint32_t>(v.size()));
    const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
    buf.insert(buf.end(), p, p + v.size() * sizeof(T));
  }
  void v3(const glm::vec3& v) { f32(v.x), f32(v.y), f32(v.z); }
  void v4(const glm::vec4& v) { f32(v.x), f32(v.y), f32(v.z), f32(v.w); }
};

void write_features(Writer& w, const bridge::MaterialFeatures& f) {
  w.i32(int(f.shading)), w.i32(int(f.alpha)), w.i32(int(f.precision));
  w.boolean(f.base_color_texture), w.boolean(f.metallic_roughness_texture), w.boolean(f.normal_texture);
  w.boolean(f.emissive_texture), w.boolean(f.occlusion_texture);
  w.u32(f.texcoord1_slots);
  w.boolean(f.texture_transform), w.boolean(f.vertex_colors), w.boolean(f.vertex_alpha);
  w.boolean(f.double_sided);
  w.i32(f.skin_joints), w.i32(f.morph_targets);
  w.boolean(f.morph_normals);
  w.i32(f.lights.directional), w.i32(f.lights.point), w.i32(f.lights.spot), w.u32(f.lights.shadows);
  w.boolean(f.environment_map_2d), w.boolean(f.has_tangents);
}

// Since version 4: the integrity table. Every region carries all three models (the unused ones
// empty), so the layout does not depend on the kind.
void write_integrity(Writer& w, const bridge::IntegrityTable& t) {
  w.i32(t.width), w.i32(t.height);
  w.u32(static_cast<std::uint32_t>(t.regions.size()));
  for (const auto& r : t.regions) {
    w.str(r.name), w.i32(int(r.kind)), w.str(r.signal), w.vec(r.bindings), w.str(r.node);
    w.u32(static_cast<std::uint32_t>(r.materials.size()));
    for (const auto& m : r.materials) w.str(m);
    w.i32(r.rect.x), w.i32(r.rect.y), w.i32(r.rect.width), w.i32(r.rect.height);
    w.vec(r.telltale.mask);
    w.u32(static_cast<std::uint32_t>(r.telltale.looks.size()));
    for (const auto& l : r.telltale.looks) w.str(l.name), w.boolean(l.lit), w.f64(l.mean[0]), w.f64(l.mean[1]), w.f64(l.mean[2]);
    w.f64(r.telltale.tolerance);
    const auto& n = r.needle;
    w.str(n.animation), w.f64(n.pivot_x), w.f64(n.pivot_y), w.f64(n.r_min), w.f64(n.r_max);
    for (int c : n.color_min) w.i32(c);
    for (int c : n.color_max) w.i32(c);
    w.i32(n.min_pixels);
    w.u32(static_cast<std::uint32_t>(n.samples.size()));
    for (const auto& s : n.samples) w.f64(s.time), w.f64(s.value), w.f64(s.angle_deg);
    w.f64(n.tolerance_deg), w.f64(n.sector_center_deg), w.f64(n.sector_half_deg);
    const auto& o = r.readout;
    w.i32(o.anchor_x), w.i32(o.baseline_y), w.i32(o.size_px), w.i32(int(o.align)), w.str(o.format), w.i32(o.tolerance_pixels);
  }
}

void write_program(Writer& w, const ProgramEntry& e) {
  const auto& p = e.program;
  w.str(p.vertex_source), w.str(p.fragment_source);
  w.u32(static_cast<std::uint32_t>(p.attributes.size()));
  for (const auto& a : p.attributes) w.str(a.name), w.i32(int(a.semantic)), w.i32(a.index), w.i32(a.location), w.i32(a.components);
  w.u32(static_cast<std::uint32_t>(p.uniforms.size()));
  for (const auto& u : p.uniforms) w.str(u.name), w.str(u.glsl_type), w.i32(int(u.semantic)), w.i32(u.index), w.i32(u.array_size);
  w.u32(static_cast<std::uint32_t>(p.samplers.size()));
  for (const auto& s : p.samplers) w.str(s.name), w.i32(int(s.slot)), w.i32(s.unit), w.i32(s.index);
  write_features(w, p.features);
  w.boolean(p.blend), w.boolean(p.cull_back_faces), w.boolean(p.optimized), w.boolean(p.uber);
  const auto& o = e.optimize_report;
  for (std::size_t v : {o.source_bytes_before, o.source_bytes_after, o.spirv_instructions_before,
                        o.spirv_instructions_after, o.uniforms_before, o.uniforms_after,
                        o.varyings_before, o.varyings_after, o.samplers_before, o.samplers_after}) {
    w.pod(static_cast<std::uint64_t>(v));
  }
  w.u32(static_cast<std::uint32_t>(o.folded.size()));
  for (const auto& f : o.folded) w.str(f);
}

// Since version 5: the draw levels (meter/bridge/draw_levels.hpp): every primitive's LOD levels in
// mesh and primitive order, then one DrawLevels per draw (or none).
void write_levels(Writer& w, const Scene& s) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      w.u32(static_cast<std::uint32_t>(p.lods.size()));
      for (const auto& l : p.lods) w.f32(l.error), w.f32(l.triangle_fraction), w.vec(l.indices);
    }
  w.u32(static_cast<std::uint32_t>(s.draw_levels.size()));
  for (const auto& d : s.draw_levels) {
    w.boolean(d.safety), w.i32(d.lods);
    w.u32(static_cast<std::uint32_t>(d.shadings.size()));
    for (const auto& l : d.shadings) w.i32(int(l.shading)), w.i32(l.program), w.v3(l.specular_color), w.f32(l.shininess), w.f32(l.base_scale);
  }
}

}  // namespace

std::vector<std::uint8_t> serialize_scene(const Scene& s) {
  Writer w;
  w.str(s.source_name);
  w.u32(static_cast<std::uint32_t>(s.nodes.size()));
  for (const auto& n : s.nodes) {
    w.str(n.name), w.i32(n.parent);
    w.vec(n.children);
    w.v3(n.translation);
    w.v4(glm::vec4(n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w));
    w.v3(n.scale);
    w.i32(n.mesh), w.i32(n.camera), w.i32(n.light), w.i32(n.skin);
    w.vec(n.weights);
  }
  w.vec(s.roots);
  w.u32(static_cast<std::uint32_t>(s.meshes.size()));
  for (const auto& m : s.meshes) {
    w.str(m.name);
    w.vec(m.weights);
    w.u32(static_cast<std::uint32_t>(m.primitives.size()));
    for (const auto& p : m.primitives) {
      w.i32(p.material), w.u32(p.vertex_count), w.i32(p.stride), w.i32(p.morph_targets);
      w.u32(static_cast<std::uint32_t>(p.layout.size()));
      for (const auto& a : p.layout) w.i32(int(a.semantic)), w.i32(a.index), w.i32(a.components), w.i32(a.offset);
      w.vec(p.vertices);
      w.vec(p.indices);
      w.v3(p.bounds_min), w.v3(p.bounds_max);
    }
  }
  w.u32(static_cast<std::uint32_t>(s.materials.size()));
  for (const auto& m : s.materials) {
    w.str(m.name), w.i32(int(m.shading)), w.i32(int(m.alpha)), w.boolean(m.double_sided);
    w.v4(m.base_color), w.v3(m.emissive);
    w.f32(m.metallic), w.f32(m.roughness), w.f32(m.normal_scale), w.f32(m.occlusion_strength), w.f32(m.alpha_cutoff);
    w.v3(m.specular_color), w.f32(m.shininess);
    for (int i = 0; i < 6; ++i) {
      w.i32(m.texture[i]), w.i32(m.texcoord[i]);
      for (int c = 0; c < 3; ++c) w.v3(m.uv_transform[i][c]);
    }
    w.boolean(m.has_uv_transform);
  }
  w.u32(static_cast<std::uint32_t>(s.textures.size()));
  for (const auto& t : s.textures) {
    w.str(t.name), w.i32(t.width), w.i32(t.height), w.vec(t.rgba), w.boolean(t.srgb);
    w.i32(t.min_filter), w.i32(t.mag_filter), w.i32(t.wrap_s), w.i32(t.wrap_t);
  }
  w.u32(static_cast<std::uint32_t>(s.cameras.size()));
  for (const auto& c : s.cameras) {
    w.str(c.name), w.boolean(c.perspective), w.f32(c.yfov), w.f32(c.znear), w.f32(c.zfar), w.f32(c.xmag), w.f32(c.ymag);
  }
  w.u32(static_cast<std::uint32_t>(s.lights.size()));
  for (const auto& l : s.lights) {
    w.str(l.name), w.i32(int(l.type)), w.v3(l.color), w.f32(l.intensity), w.f32(l.range), w.f32(l.inner_cone), w.f32(l.outer_cone),
        w.boolean(l.cast_shadow);
  }
  w.u32(static_cast<std::uint32_t>(s.skins.size()));
  for (const auto& k : s.skins) {
    w.str(k.name), w.vec(k.joints);
    w.u32(static_cast<std::uint32_t>(k.inverse_bind.size()));
    for (const auto& m : k.inverse_bind) {
      for (int c = 0; c < 4; ++c) w.v4(m[c]);
    }
  }
  w.u32(static_cast<std::uint32_t>(s.animations.size()));
  for (const auto& a : s.animations) {
    w.str(a.name), w.f32(a.start), w.f32(a.end);
    w.u32(static_cast<std::uint32_t>(a.samplers.size()));
    for (const auto& sm : a.samplers) w.i32(int(sm.interpolation)), w.i32(sm.components), w.vec(sm.input), w.vec(sm.output);
    w.u32(static_cast<std::uint32_t>(a.channels.size()));
    for (const auto& ch : a.channels) w.i32(ch.sampler), w.i32(ch.node), w.i32(int(ch.path));
  }
  w.u32(static_cast<std::uint32_t>(s.programs.size()));
  for (const auto& p : s.programs) write_program(w, p);
  w.u32(static_cast<std::uint32_t>(s.draws.size()));
  for (const auto& d : s.draws) w.i32(d.node), w.i32(d.mesh), w.i32(d.primitive), w.i32(d.program);
  w.u32(static_cast<std::uint32_t>(s.groups.size()));  // since version 2: mesh concatenation groups
  for (const auto& g : s.groups) w.str(g.name), w.vec(g.draws);
  // since version 3: the world environment; since 7 its reflection probe where a texture index was
  w.i32(s.environment.probe.face_size), w.i32(s.environment.probe.levels), w.vec(s.environment.probe.rgb);
  w.f32(s.environment.strength);
  for (const auto& e : s.environment.irradiance) w.v3(e);
  w.str(s.config.source_json);
  write_integrity(w, s.integrity);
  write_levels(w, s);

  Writer out;
  out.buf.insert(out.buf.end(), std::begin(kPackageMagic), std::end(kPackageMagic));
  out.u32(kPackageVersion);
  out.u32(0);
  out.pod(static_cast<std::uint64_t>(w.buf.size()));
  out.pod(package_checksum(w.buf));
  out.buf.insert(out.buf.end(), w.buf.begin(), w.buf.end());
  return std::move(out.buf);
}

void write_package(const Scene& scene, const std::string& path) {
  auto bytes = serialize_scene(scene);
  // A temporary name of this writer's own (process id and a per-process count), so two
  // conversions of the same package at once (two build jobs, two test processes) never write
  // into each other's file; the last rename wins and both leave a whole package.
  static std::atomic<unsigned> writes{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(writes++);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw SceneError(path + ": cannot open " + tmp + " for writing: " + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      throw SceneError(path + ": write failed (" + tmp + ")");
    }
  }
  // Rename so a viewer never sees a half-written package.
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw SceneError(path + ": cannot rename " + tmp + " onto it: " + why);
  }
}

}  // namespace meter::convert
