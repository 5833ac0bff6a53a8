// The quality ladder: see quality_ladder.hpp.
#include "meter/convert/quality_ladder.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <utility>

#include <meshoptimizer.h>

#include "meter/convert/flat_geometry.hpp"
#include "programs/program_features.hpp"

namespace meter::convert {

namespace {
// Affine interpolation: every user varying gets the `noperspective` qualifier of
// NV_shader_noperspective_interpolation. Vertex outputs and fragment inputs are the varyings
// (vertex inputs are attributes, the fragment output is the colour); `flat` ones stay as they are.
std::string make_affine(const std::string& source, bool vertex_stage) {
  const std::string qualifier = vertex_stage ? "out " : "in ";
  std::istringstream in(source);
  std::ostringstream out;
  std::string line;
  bool extension_added = false;
  while (std::getline(in, line)) {
    std::size_t body = 0;
    if (line.rfind("layout(", 0) == 0) {  // SPIRV-Cross output: "layout(location = 0) in ..."
      const auto close = line.find(')');
      body = close == std::string::npos ? 0 : line.find_first_not_of(' ', close + 1);
      if (body == std::string::npos) body = 0;
    }
    if (line.compare(body, qualifier.size(), qualifier) == 0 && line.find("gl_") == std::string::npos)
      line.insert(body, "noperspective ");
    out << line << '\n';
    if (!extension_added && line.rfind("#version", 0) == 0) {
      out << "#extension GL_NV_shader_noperspective_interpolation : require\n";
      extension_added = true;
    }
  }
  if (!extension_added) throw SceneError("interpolation=affine: a program source has no #version line");
  return out.str();
}


using shadergen::AttributeSemantic;
using shadergen::ShadingModel;
using shadergen::TextureSlot;

constexpr int kGlNearest = 0x2600, kGlLinear = 0x2601, kGlLinearMipmapLinear = 0x2703;


// A PBR material shown with a Blinn-Phong-style model: its mapped parameters (pbr_as_phong).
void map_pbr_to_phong(Material& m) {
  const PhongParameters p = pbr_as_phong(m);
  m.shininess = p.shininess;
  m.specular_color = p.specular_color;
  m.base_color = glm::vec4(glm::vec3(m.base_color) * p.base_scale, m.base_color.a);
}

void simplify(Primitive& p, float lod, QualityReport& report) {
  const auto pos = std::find_if(p.layout.begin(), p.layout.end(),
                                 [](const VertexAttribute& v) { return v.semantic == AttributeSemantic::Position; });
  if (pos == p.layout.end() || p.indices.size() < 3 || lod >= 1.0f) return;
  const std::size_t target = std::max<std::size_t>(3, std::size_t(double(p.indices.size() / 3) * lod) * 3);
  std::vector<unsigned int> out(p.indices.size());
  float error = 0.0f;
  // target_error 1 (the whole mesh extent): the ladder asks for a triangle budget, and the error
  // reached is reported instead of limiting it.
  const std::size_t n = meshopt_simplify(out.data(), p.indices.data(), p.indices.size(), p.vertices.data() + pos->offset,
                                         p.vertex_count, std::size_t(p.stride) * sizeof(float), target, 1.0f, 0, &error);
  if (n == 0) return;  // nothing left that keeps the topology valid: keep the original
  report.triangles_before += p.indices.size() / 3;
  report.triangles_after += n / 3;
  report.max_simplify_error = std::max(report.max_simplify_error, error);
  ++report.primitives_simplified;
  out.resize(n);
  p.indices.assign(out.begin(), out.end());
  p.flat_indices.clear();  // made again for the new triangles (apply_quality's last step)
  for (LodLevel& l : p.lods) l.flat_indices.clear();
}

}  // namespace

// The spelling is shadergen's (to_string), so the ladder and meter-shadergen agree on names.
std::optional<ShadingModel> parse_shading_model(const std::string& t) {
  for (ShadingModel m : {ShadingModel::Unlit, ShadingModel::Flat, ShadingModel::Gouraud,
                         ShadingModel::BlinnPhong, ShadingModel::PbrMetallicRoughness}) {
    if (t == shadergen::to_string(m)) return m;
  }
  return std::nullopt;
}

const char* filter_name(TextureFilter f) {
  switch (f) {
    case TextureFilter::Nearest: return "nearest";
    case TextureFilter::Bilinear: return "bilinear";
    case TextureFilter::Trilinear: return "trilinear";
    case TextureFilter::Anisotropic: return "anisotropic";
  }
  return "?";
}

namespace {

// The settings each node gets: the global ones with the node's own overrides on top. Checks the
// settings against the scene (msaa, lod fractions, object names) on construction.
class NodeQuality {
 public:
  NodeQuality(const Scene& s, const QualitySettings& q, const std::string& where)
      : global_(q.global), per_node_(s.nodes.size(), nullptr) {
    if (q.msaa && *q.msaa != 1 && *q.msaa != 2 && *q.msaa != 4 && *q.msaa != 8)
      throw SceneError(where + "msaa = " + std::to_string(*q.msaa) + ", expected 1, 2, 4 or 8");
    auto check_lod = [&](const QualityOverride& o, const std::string& who) {
      if (o.lod && !(*o.lod > 0.0f && *o.lod <= 1.0f))
        throw SceneError(where + who + ": lod = " + std::to_string(*o.lod) + ", expected a fraction of triangles in (0, 1]");
    };
    check_lod(q.global, "global");
    for (const auto& [name, o] : q.objects) {
      const int n = s.find_node(name);
      if (n < 0) throw SceneError(where + "objects.\"" + name + "\": no node of that name in the scene");
      check_lod(o, "objects.\"" + name + "\"");
      per_node_[std::size_t(n)] = &o;
    }
  }

  QualityOverride at(int node) const {
    QualityOverride e = global_;
    if (const QualityOverride* o = per_node_[std::size_t(node)]) {
      if (o->shading) e.shading = o->shading;
      if (o->precision) e.precision = o->precision;
      if (o->lod) e.lod = o->lod;
    }
    return e;
  }

 private:
  QualityOverride global_;
  std::vector<const QualityOverride*> per_node_;
};

// Scene-wide settings: the resolve and sample shading, and the environment and shadow maps the
// settings turn off.
void apply_scene_settings(Scene& s, const QualitySettings& q, QualityReport& report) {
  if (q.resolve) s.config.resolve.filter = *q.resolve;
  if (q.sample_format) s.config.resolve.sample_format = *q.sample_format;
  if (q.sample_shading) s.config.sample_shading = *q.sample_shading;
  if (q.environment == false && s.environment.present()) {
    // The probe and the ambient cube go; the programs stop sampling them (regenerate_programs).
    s.environment = Environment{};
    report.environment_dropped = true;
  }
  if (q.shadows == false)
    for (Light& l : s.lights) report.shadow_maps_dropped += std::exchange(l.cast_shadow, false) ? 1 : 0;
}

// Programs: regenerate those whose draws ask for another model / precision, or that sample an
// environment or shadow maps the settings dropped (deduplicated by key).
void regenerate_programs(Scene& s, const NodeQuality& quality, const std::string& where, QualityReport& report) {
  std::map<std::string, int> cache;
  std::set<int> mapped_materials;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    DrawItem& d = s.draws[i];
    const QualityOverride e = quality.at(d.node);
    const shadergen::MaterialFeatures& stored = s.programs[std::size_t(d.program)].program.features;
    // An environment or shadow maps the settings dropped: the program must stop sampling them.
    const bool drop_maps = (stored.environment_map_2d && !s.environment.present()) ||
                                  (stored.lights.shadows != 0 && report.shadow_maps_dropped > 0);
    if (!e.shading && !e.precision && !drop_maps) continue;
    const ShadingModel shading = e.shading.value_or(stored.shading);
    const shadergen::Precision precision = e.precision.value_or(stored.precision);
    if (shading == stored.shading && precision == stored.precision && !drop_maps) continue;
    const int mat = s.meshes[std::size_t(d.mesh)].primitives[std::size_t(d.primitive)].material;
    if ((shading == ShadingModel::BlinnPhong || shading == ShadingModel::Gouraud) &&
        s.materials[std::size_t(mat)].shading == ShadingModel::PbrMetallicRoughness && mapped_materials.insert(mat).second)
      map_pbr_to_phong(s.materials[std::size_t(mat)]);
    const shadergen::MaterialFeatures f = features_at(s, d, stored, shading, precision);
    const std::string key = shadergen::program_key(f);
    auto it = cache.find(key);
    if (it == cache.end()) {
      ProgramEntry pe;
      try {
        pe.program = shadergen::generate(f);
      } catch (const std::exception& ex) {
        throw SceneError(where + "node \"" + s.nodes[std::size_t(d.node)].name + "\" (features " + key + "): " + ex.what());
      }
      it = cache.emplace(key, int(s.programs.size())).first;
      s.programs.push_back(std::move(pe));
      ++report.programs_regenerated;
    }
    d.program = it->second;
  }
}

// A merged group draws all members with one program: split programs end the merge.
void drop_split_groups(Scene& s, QualityReport& report) {
  const std::size_t groups_before = s.groups.size();
  std::erase_if(s.groups, [&](const MergedGroup& g) {
    return std::any_of(g.draws.begin(), g.draws.end(), [&](int d) {
      return s.draws[std::size_t(d)].program != s.draws[std::size_t(g.draws.front())].program;
    });
  });
  report.groups_dropped = int(groups_before - s.groups.size());
}

// LOD: per mesh, one simplified copy per distinct fraction asked for (a mesh shared by nodes
// with different fractions is duplicated so each node gets its own).
void simplify_meshes(Scene& s, const NodeQuality& quality, QualityReport& report) {
  std::map<std::pair<int, float>, int> lod_mesh;
  std::map<int, float> first_lod;  // mesh -> the fraction its own (in-place) copy was given
  for (DrawItem& d : s.draws) {
    const float lod = quality.at(d.node).lod.value_or(1.0f);
    if (lod >= 1.0f) continue;
    auto it = lod_mesh.find({d.mesh, lod});
    if (it == lod_mesh.end()) {
      int target = d.mesh;
      const bool shared = std::any_of(s.draws.begin(), s.draws.end(), [&](const DrawItem& o) {
        return o.mesh == d.mesh && quality.at(o.node).lod.value_or(1.0f) != lod;
      });
      if (shared || first_lod.count(d.mesh)) {
        target = int(s.meshes.size());
        Mesh copy = s.meshes[std::size_t(d.mesh)];
        copy.name += ".lod" + std::to_string(lod);
        s.meshes.push_back(std::move(copy));
      } else {
        first_lod[d.mesh] = lod;
      }
      for (Primitive& p : s.meshes[std::size_t(target)].primitives) simplify(p, lod, report);
      it = lod_mesh.emplace(std::make_pair(d.mesh, lod), target).first;
    }
    d.mesh = it->second;
    s.nodes[std::size_t(d.node)].mesh = it->second;
  }
}

void set_texture_filter(Scene& s, TextureFilter filter, QualityReport& report) {
  for (Texture& t : s.textures) {
    t.mag_filter = filter == TextureFilter::Nearest ? kGlNearest : kGlLinear;
    t.min_filter = filter == TextureFilter::Nearest    ? kGlNearest
                   : filter == TextureFilter::Bilinear ? kGlLinear
                                                       : kGlLinearMipmapLinear;
    // 16x: the usual ceiling of hardware and of llvmpipe; the renderer clamps to the driver's.
    t.max_anisotropy = filter == TextureFilter::Anisotropic ? 16.0f : 1.0f;
    ++report.textures_changed;
  }
}

void make_programs_affine(Scene& s, QualityReport& report) {
  for (ProgramEntry& e : s.programs) {
    e.program.vertex_source = make_affine(e.program.vertex_source, true);
    e.program.fragment_source = make_affine(e.program.fragment_source, false);
    ++report.programs_made_affine;
  }
}

}  // namespace

QualityReport apply_quality(Scene& s, const QualitySettings& q) {
  QualityReport report;
  const std::string where = s.source_name + ": quality: ";
  const NodeQuality quality(s, q, where);
  apply_scene_settings(s, q, report);
  regenerate_programs(s, quality, where, report);
  drop_split_groups(s, report);
  simplify_meshes(s, quality, report);
  if (q.filter) set_texture_filter(s, *q.filter, report);
  if (q.affine == true) make_programs_affine(s, report);
  // Draws now shaded Flat, or simplified, get their Flat lists.
  prepare_flat_draws(s);
  return report;
}

QualitySettings parse_quality(const std::string& text) {
  QualitySettings q;
  std::stringstream ss(text);
  std::string pair;
  while (std::getline(ss, pair, ',')) {
    if (pair.empty() || pair == "default") continue;
    const auto eq = pair.find('=');
    if (eq == std::string::npos) throw SceneError("quality \"" + text + "\": \"" + pair + "\" is not key=value");
    const std::string k = pair.substr(0, eq), v = pair.substr(eq + 1);
    auto bad = [&](const std::string& expected) {
      return SceneError("quality \"" + text + "\": " + k + " = \"" + v + "\", expected " + expected);
    };
    if (k == "shading") {
      q.global.shading = parse_shading_model(v);
      if (!q.global.shading) throw bad("unlit, flat, gouraud, blinn-phong or pbr");
    } else if (k == "precision") {
      if (v == "mediump") q.global.precision = shadergen::Precision::Mediump;
      else if (v == "highp") q.global.precision = shadergen::Precision::Highp;
      else throw bad("mediump or highp");
    } else if (k == "filter") {
      if (v == "nearest") q.filter = TextureFilter::Nearest;
      else if (v == "bilinear") q.filter = TextureFilter::Bilinear;
      else if (v == "trilinear") q.filter = TextureFilter::Trilinear;
      else if (v == "anisotropic") q.filter = TextureFilter::Anisotropic;
      else throw bad("nearest, bilinear, trilinear or anisotropic");
    } else if (k == "msaa") {
      if (v != "1" && v != "2" && v != "4" && v != "8") throw bad("1, 2, 4 or 8");
      q.msaa = std::stoi(v);
    } else if (k == "interpolation") {
      if (v == "affine") q.affine = true;
      else if (v == "perspective") q.affine = false;
      else throw bad("affine or perspective");
    } else if (k == "environment") {
      if (v == "on") q.environment = true;
      else if (v == "off") q.environment = false;
      else throw bad("on or off");
    } else if (k == "shadows") {
      if (v == "on") q.shadows = true;
      else if (v == "off") q.shadows = false;
      else throw bad("on or off");
    } else if (k == "resolve") {
      if (v == "box") q.resolve = bridge::ResolveConfig::Filter::Box;
      else if (v == "blackman-harris") q.resolve = bridge::ResolveConfig::Filter::BlackmanHarris;
      else throw bad("box or blackman-harris");
    } else if (k == "sample_format") {
      if (v == "srgb8") q.sample_format = bridge::ResolveConfig::SampleFormat::Srgb8;
      else if (v == "rgba16f") q.sample_format = bridge::ResolveConfig::SampleFormat::Rgba16f;
      else throw bad("srgb8 or rgba16f");
    } else if (k == "sample_shading") {
      bridge::SampleShading kinds;
      if (v == "normal-maps+mirrors") kinds = {.normal_maps = true, .mirrors = true};
      else if (v == "normal-maps") kinds.normal_maps = true;
      else if (v == "mirrors") kinds.mirrors = true;
      else if (v != "off") throw bad("off, normal-maps, mirrors or normal-maps+mirrors");
      q.sample_shading = kinds;
    } else if (k == "lod") {
      char* end = nullptr;
      const float f = std::strtof(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(f > 0.0f && f <= 1.0f)) throw bad("a fraction of triangles in (0, 1]");
      q.global.lod = f;
    } else {
      throw SceneError("quality \"" + text + "\": unknown key \"" + k + "\" (expected shading, precision, filter, msaa, lod, environment, shadows, interpolation, resolve, sample_format, sample_shading)");
    }
  }
  return q;
}

std::string describe_quality(const QualitySettings& q) {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : ",") + s; };
  if (q.global.shading) add(std::string("shading=") + shadergen::to_string(*q.global.shading));
  if (q.global.precision) add(std::string("precision=") + (*q.global.precision == shadergen::Precision::Mediump ? "mediump" : "highp"));
  if (q.global.lod) {
    std::ostringstream o;
    o << "lod=" << *q.global.lod;
    add(o.str());
  }
  if (q.filter) add(std::string("filter=") + filter_name(*q.filter));
  if (q.msaa) add("msaa=" + std::to_string(*q.msaa));
  if (q.environment) add(std::string("environment=") + (*q.environment ? "on" : "off"));
  if (q.shadows) add(std::string("shadows=") + (*q.shadows ? "on" : "off"));
  if (q.affine) add(std::string("interpolation=") + (*q.affine ? "affine" : "perspective"));
  if (q.resolve) add(std::string("resolve=") + (*q.resolve == bridge::ResolveConfig::Filter::Box ? "box" : "blackman-harris"));
  if (q.sample_format)
    add(std::string("sample_format=") + (*q.sample_format == bridge::ResolveConfig::SampleFormat::Rgba16f ? "rgba16f" : "srgb8"));
  if (q.sample_shading) {
    const bridge::SampleShading& k = *q.sample_shading;
    add(std::string("sample_shading=") + (k.normal_maps && k.mirrors ? "normal-maps+mirrors" : k.normal_maps ? "normal-maps" : k.mirrors ? "mirrors" : "off"));
  }
  return out.empty() ? "default" : out;
}

}  // namespace meter::convert
