// glTF -> Scene. Three phases:
//   1. load with tinygltf (syntax, buffers, image decoding);
//   2. validate every element, used or not, collecting all errors (and repairing the few problems
//      that have one obviously right answer, reported as warnings);
//   3. convert the nodes of the default scene into the runtime model, then generate programs.
#include "meter/engine/converter.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "meter/engine/animation.hpp"
#include "meter/engine/concatenation.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/shadergen/glsl.hpp"

namespace meter::engine {

ConvertError::ConvertError(const std::string& file, std::vector<Diagnostic> errs)
    : SceneError([&] {
        std::ostringstream os;
        os << file << ": " << errs.size() << (errs.size() == 1 ? " error" : " errors");
        std::size_t shown = 0;
        for (const auto& e : errs) {
          if (++shown > 50) {
            os << "\n  ... " << errs.size() - 50 << " more";
            break;
          }
          os << "\n  " << e.path << ": " << e.message;
        }
        return os.str();
      }()),
      errors(std::move(errs)) {}

namespace {

using shadergen::AttributeSemantic;
using shadergen::TextureSlot;

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

int component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "?";
  }
}

std::string idx(const char* what, std::size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

class Converter {
 public:
  Converter(const tinygltf::Model& m, std::string file, const SceneConfig& cfg, const ConvertOptions& opt)
      : m_(m), file_(std::move(file)), cfg_(cfg), opt_(opt) {}

  ConvertResult run() {
    validate();
    if (!errors_.empty()) {
      ConvertError e(file_, errors_);
      e.repairs = repairs_;
      throw e;
    }
    ConvertResult r;
    r.scene = build();
    r.repairs = repairs_;
    r.concat_report = concat_report(plan_);
    return r;
  }

 private:
  const tinygltf::Model& m_;
  std::string file_;
  const SceneConfig& cfg_;
  ConvertOptions opt_;
  std::vector<Diagnostic> errors_, repairs_;
  std::vector<char> accessor_ok_;
  std::vector<std::vector<double>> accessor_cache_;
  std::vector<int> parent_;
  std::vector<char> node_ok_;
  std::vector<char> in_loop_;
  platform::Image environment_;  // decoded `meter_environment` image (empty = none)
  float environment_strength_ = 1.0f;
  std::string environment_name_;
  ConcatPlan plan_;              // mesh concatenation groups (issue #10)
  std::set<int> group_members_;  // nodes merged at runtime: their programs get vertex_alpha

  void error(const std::string& path, const std::string& msg) { errors_.push_back({path, msg}); }
  void repair(const std::string& path, const std::string& msg) { repairs_.push_back({path, msg}); }

  // ---------------------------------------------------------------- accessors
  void check_accessor(std::size_t i) {
    const auto& a = m_.accessors[i];
    const std::string p = idx("accessors", i);
    const int cs = component_size(a.componentType);
    const int nc = type_components(a.type);
    bool ok = true;
    if (!cs) error(p + ".componentType", "unsupported component type " + std::to_string(a.componentType)), ok = false;
    if (!nc) error(p + ".type", "unsupported accessor type"), ok = false;
    if (a.count == 0) error(p + ".count", "must be at least 1"), ok = false;
    if (ok && a.bufferView >= 0) {
      if (static_cast<std::size_t>(a.bufferView) >= m_.bufferViews.size()) {
        error(p + ".bufferView", "index " + std::to_string(a.bufferView) + " out of range"), ok = false;
      } else {
        const auto& bv = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
        const std::string bvp = idx("bufferViews", static_cast<std::size_t>(a.bufferView));
        if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size()) {
          error(bvp + ".buffer", "index out of range"), ok = false;
        } else if (bv.byteOffset + bv.byteLength > m_.buffers[static_cast<std::size_t>(bv.buffer)].data.size()) {
          error(bvp + ".byteLength", "buffer view (offset " + std::to_string(bv.byteOffset) + ", length " +
                                         std::to_string(bv.byteLength) + ") does not fit buffer " +
                                         std::to_string(bv.buffer) + " (" +
                                         std::to_string(m_.buffers[static_cast<std::size_t>(bv.buffer)].data.size()) + " bytes)");
          ok = false;
        } else {
          const std::size_t elem = std::size_t(cs) * std::size_t(nc);
          const std::size_t stride = bv.byteStride ? bv.byteStride : elem;
          if (bv.byteStride && (bv.byteStride < elem || bv.byteStride % std::size_t(cs))) {
            error(bvp + ".byteStride", "stride " + std::to_string(bv.byteStride) + " is invalid for " + type_name(a.type)), ok = false;
          } else if (a.byteOffset + stride * (a.count - 1) + elem > bv.byteLength) {
            error(p, "accessor data (offset " + std::to_string(a.byteOffset) + ", " + std::to_string(a.count) +
                         " elements) does not fit bufferViews[" + std::to_string(a.bufferView) + "] (" +
                         std::to_string(bv.byteLength) + " bytes)");
            ok = false;
          }
        }
      }
    }
    if (ok && a.sparse.isSparse) {
      auto check_view = [&](int v, std::size_t off, std::size_t bytes, const std::string& sp) {
        if (v < 0 || static_cast<std::size_t>(v) >= m_.bufferViews.size()) {
          error(sp + ".bufferView", "index out of range"), ok = false;
          return;
        }
        const auto& bv = m_.bufferViews[static_cast<std::size_t>(v)];
        if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size() ||
            bv.byteOffset + bv.byteLength > m_.buffers[static_cast<std::size_t>(bv.buffer)].data.size() ||
            off + bytes > bv.byteLength) {
          error(sp, "sparse data does not fit its buffer view"), ok = false;
        }
      };
      const int ics = component_size(a.sparse.indices.componentType);
      if (a.sparse.count <= 0 || static_cast<std::size_t>(a.sparse.count) > a.count || !ics ||
          a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
          a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT) {
        error(p + ".sparse", "invalid sparse count or index component type"), ok = false;
      } else {
        check_view(a.sparse.indices.bufferView, std::size_t(a.sparse.indices.byteOffset),
                   std::size_t(a.sparse.count) * std::size_t(ics), p + ".sparse.indices");
        check_view(a.sparse.values.bufferView, std::size_t(a.sparse.values.byteOffset),
                   std::size_t(a.sparse.count) * std::size_t(cs) * std::size_t(nc), p + ".sparse.values");
      }
    }
    accessor_ok_[i] = ok;
    if (!ok) return;
    // Decode now: every later check and the conversion read the decoded doubles.
    auto& out = accessor_cache_[i];
    out.assign(a.count * std::size_t(nc), 0.0);
    auto decode = [&](const unsigned char* src, int ct, bool normalized) -> double {
      switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, src, 4); return f; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, src, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, src, 2); return normalized ? v / 65535.0 : v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { std::int16_t v; std::memcpy(&v, src, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *src / 255.0 : *src;
        case TINYGLTF_COMPONENT_TYPE_BYTE: { auto v = static_cast<std::int8_t>(*src); return normalized ? std::max(v / 127.0, -1.0) : v; }
        default: return 0.0;
      }
    };
    if (a.bufferView >= 0) {
      const auto& bv = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
      const auto& buf = m_.buffers[static_cast<std::size_t>(bv.buffer)].data;
      const std::size_t stride = bv.byteStride ? bv.byteStride : std::size_t(cs) * std::size_t(nc);
      for (std::size_t e = 0; e < a.count; ++e) {
        const unsigned char* base = buf.data() + bv.byteOffset + a.byteOffset + e * stride;
        for (int c = 0; c < nc; ++c) out[e * std::size_t(nc) + std::size_t(c)] = decode(base + c * cs, a.componentType, a.normalized);
      }
    }
    if (a.sparse.isSparse) {
      const auto& ibv = m_.bufferViews[static_cast<std::size_t>(a.sparse.indices.bufferView)];
      const auto& vbv = m_.bufferViews[static_cast<std::size_t>(a.sparse.values.bufferView)];
      const auto* ib = m_.buffers[static_cast<std::size_t>(ibv.buffer)].data.data() + ibv.byteOffset + std::size_t(a.sparse.indices.byteOffset);
      const auto* vb = m_.buffers[static_cast<std::size_t>(vbv.buffer)].data.data() + vbv.byteOffset + std::size_t(a.sparse.values.byteOffset);
      const int ics = component_size(a.sparse.indices.componentType);
      for (int s = 0; s < a.sparse.count; ++s) {
        auto target = static_cast<std::size_t>(decode(ib + s * ics, a.sparse.indices.componentType, false));
        if (target >= a.count) {
          error(p + ".sparse.indices", "sparse index " + std::to_string(target) + " >= count " + std::to_string(a.count));
          accessor_ok_[i] = false;
          return;
        }
        for (int c = 0; c < nc; ++c) out[target * std::size_t(nc) + std::size_t(c)] = decode(vb + (s * nc + c) * cs, a.componentType, a.normalized);
      }
    }
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
      for (std::size_t e = 0; e < out.size(); ++e) {
        if (!std::isfinite(out[e])) {
          error(p, "element " + std::to_string(e / std::size_t(nc)) + " (component " + std::to_string(e % std::size_t(nc)) +
                       ") is " + (std::isnan(out[e]) ? "NaN" : (out[e] > 0 ? "Infinity" : "-Infinity")));
          accessor_ok_[i] = false;
        }
      }
    }
  }

  // Validated accessor `a` used as `path`, with an expected type; returns nullptr (after an error) when unusable.
  const std::vector<double>* use_accessor(int a, const std::string& path, std::initializer_list<int> types,
                                          std::initializer_list<int> component_types) {
    if (a < 0 || static_cast<std::size_t>(a) >= m_.accessors.size()) {
      error(path, "accessor index " + std::to_string(a) + " out of range");
      return nullptr;
    }
    const auto& acc = m_.accessors[static_cast<std::size_t>(a)];
    if (std::find(types.begin(), types.end(), acc.type) == types.end()) {
      std::string list;
      for (int t : types) list += std::string(list.empty() ? "" : " or ") + type_name(t);
      error(path, std::string("accessor type ") + type_name(acc.type) + " where " + list + " is required");
      return nullptr;
    }
    if (component_types.size() &&
        std::find(component_types.begin(), component_types.end(), acc.componentType) == component_types.end()) {
      error(path, "component type " + std::to_string(acc.componentType) + " is not allowed here");
      return nullptr;
    }
    if (!accessor_ok_[static_cast<std::size_t>(a)]) return nullptr;  // already reported at accessors[a]
    return &accessor_cache_[static_cast<std::size_t>(a)];
  }

  // ---------------------------------------------------------------- validation
  void validate() {
    static const std::set<std::string> supported{"KHR_lights_punctual", "KHR_materials_unlit", "KHR_texture_transform",
                                                 "KHR_materials_emissive_strength", "KHR_mesh_quantization"};
    for (std::size_t i = 0; i < m_.extensionsRequired.size(); ++i) {
      if (!supported.count(m_.extensionsRequired[i])) {
        error(idx("extensionsRequired", i), "extension " + m_.extensionsRequired[i] + " is required by the file but not supported");
      }
    }
    accessor_ok_.assign(m_.accessors.size(), 0);
    accessor_cache_.assign(m_.accessors.size(), {});
    for (std::size_t i = 0; i < m_.accessors.size(); ++i) check_accessor(i);
    validate_nodes();
    for (std::size_t i = 0; i < m_.meshes.size(); ++i) validate_mesh(i);
    for (std::size_t i = 0; i < m_.skins.size(); ++i) validate_skin(i);
    for (std::size_t i = 0; i < m_.animations.size(); ++i) validate_animation(i);
    for (std::size_t i = 0; i < m_.materials.size(); ++i) validate_material(i);
    for (std::size_t i = 0; i < m_.textures.size(); ++i) {
      const auto& t = m_.textures[i];
      if (t.source < 0 || static_cast<std::size_t>(t.source) >= m_.images.size()) {
        error(idx("textures", i) + ".source", "image index " + std::to_string(t.source) + " out of range");
      } else {
        const auto& im = m_.images[static_cast<std::size_t>(t.source)];
        if (im.image.empty() || im.width <= 0 || im.height <= 0 || im.component < 1 || im.component > 4 || im.bits != 8 ||
            im.image.size() != std::size_t(im.width) * std::size_t(im.height) * std::size_t(im.component)) {
          error(idx("images", std::size_t(t.source)), "image could not be decoded to 8-bit pixels (PNG/JPEG expected)");
        }
      }
      if (t.sampler >= 0 && static_cast<std::size_t>(t.sampler) >= m_.samplers.size()) {
        error(idx("textures", i) + ".sampler", "sampler index out of range");
      }
    }
    for (std::size_t i = 0; i < m_.cameras.size(); ++i) {
      const auto& c = m_.cameras[i];
      const std::string p = idx("cameras", i);
      if (c.type == "perspective") {
        if (!(c.perspective.yfov > 0 && c.perspective.yfov < 3.14159)) error(p + ".perspective.yfov", "must be in (0, pi), got " + fmt(c.perspective.yfov));
        if (!(c.perspective.znear > 0)) error(p + ".perspective.znear", "must be > 0");
        if (c.perspective.zfar != 0 && !(c.perspective.zfar > c.perspective.znear)) error(p + ".perspective.zfar", "must be > znear");
      } else if (c.type == "orthographic") {
        if (c.orthographic.xmag == 0 || c.orthographic.ymag == 0) error(p + ".orthographic", "xmag and ymag must be non-zero");
        if (!(c.orthographic.zfar > c.orthographic.znear) || c.orthographic.znear < 0) error(p + ".orthographic.zfar", "must be > znear >= 0");
      } else {
        error(p + ".type", "expected \"perspective\" or \"orthographic\"");
      }
    }
    for (std::size_t i = 0; i < m_.lights.size(); ++i) {
      const auto& l = m_.lights[i];
      const std::string p = "extensions.KHR_lights_punctual.lights[" + std::to_string(i) + "]";
      if (l.type != "directional" && l.type != "point" && l.type != "spot") error(p + ".type", "unknown light type \"" + l.type + "\"");
      if (!(l.intensity >= 0) || !std::isfinite(l.intensity)) error(p + ".intensity", "must be a finite number >= 0");
      if (l.range < 0 || !std::isfinite(l.range)) error(p + ".range", "must be > 0 when present");
      if (l.type == "spot" && !(l.spot.innerConeAngle >= 0 && l.spot.innerConeAngle < l.spot.outerConeAngle &&
                                l.spot.outerConeAngle <= 1.5707964)) {
        error(p + ".spot", "need 0 <= innerConeAngle < outerConeAngle <= pi/2");
      }
    }
    const int scene = m_.defaultScene >= 0 ? m_.defaultScene : 0;
    if (!m_.scenes.empty() && static_cast<std::size_t>(scene) >= m_.scenes.size()) error("scene", "index out of range");
    else if (!m_.scenes.empty()) validate_environment(static_cast<std::size_t>(scene));
    for (std::size_t s = 0; s < m_.scenes.size(); ++s) {
      for (int n : m_.scenes[s].nodes) {
        if (n < 0 || static_cast<std::size_t>(n) >= m_.nodes.size()) error(idx("scenes", s) + ".nodes", "node index " + std::to_string(n) + " out of range");
        else if (parent_[static_cast<std::size_t>(n)] >= 0) error(idx("scenes", s) + ".nodes", "node " + std::to_string(n) + " is not a root node");
      }
    }
  }

  // The world image Blender lit the scene with, named in the default scene's extras (Blender's
  // exporter writes custom properties there; glTF itself has no environment map). The file is
  // read relative to the glTF file and packed, so the package stays self-contained.
  void validate_environment(std::size_t scene) {
    const tinygltf::Value& extras = m_.scenes[scene].extras;
    const std::string p = idx("scenes", scene) + ".extras.";
    if (!extras.IsObject()) return;
    const bool has_file = extras.Has("meter_environment"), has_strength = extras.Has("meter_environment_strength");
    if (has_strength) {
      const tinygltf::Value& v = extras.Get("meter_environment_strength");
      const double k = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!v.IsNumber() || !std::isfinite(k) || k < 0.0 || k > 1e6) {
        error(p + "meter_environment_strength", "expected a finite number >= 0 (Blender's Background strength)");
      } else {
        environment_strength_ = static_cast<float>(k);
      }
      if (!has_file) error(p + "meter_environment_strength", "given without meter_environment (the image it scales)");
    }
    if (!has_file) return;
    const tinygltf::Value& v = extras.Get("meter_environment");
    if (!v.IsString() || v.Get<std::string>().empty()) {
      error(p + "meter_environment", "expected the file name of an equirectangular PNG, relative to the glTF file");
      return;
    }
    environment_name_ = v.Get<std::string>();
    const std::filesystem::path file = std::filesystem::path(file_).parent_path() / environment_name_;
    try {
      environment_ = platform::read_png(file);
    } catch (const platform::ImageError& e) {
      error(p + "meter_environment", "cannot use \"" + environment_name_ + "\": " + e.what());
      return;
    }
    // Two texels per axis at least (the ambient cube and the mip chain need an image), and within
    // what a package stores.
    if (environment_.width < 2 || environment_.height < 2 || environment_.width > 16384 || environment_.height > 16384) {
      error(p + "meter_environment", file.string() + ": " + std::to_string(environment_.width) + "x" +
                                         std::to_string(environment_.height) + " pixels; expected 2..16384 per side");
      environment_ = {};
    }
  }

  // EEVEE's world ambient cube (shadergen kAmbientCube): for each signed axis a, the cosine-weighted
  // mean of the map's linear radiance over the hemisphere around a, sum L max(0, d.a) dw / sum
  // max(0, d.a) dw, with the texel directions of shadergen's equirect_uv (Blender's mapping).
  static std::array<glm::vec3, 6> ambient_cube(const platform::Image& im, float strength) {
    constexpr double kPi = 3.14159265358979323846;
    std::array<double, 256> lin{};
    for (int c = 0; c < 256; ++c) lin[std::size_t(c)] = platform::srgb_to_linear(c / 255.0);
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    glm::dvec3 sum[6] = {};
    double weight[6] = {};
    for (int y = 0; y < im.height; ++y) {
      const double lat = (0.5 - (y + 0.5) / im.height) * kPi;  // row 0 = straight up (t = 0)
      const double solid_angle = std::cos(lat);                  // per texel, up to a constant
      for (int x = 0; x < im.width; ++x) {
        const double phi = ((x + 0.5) / im.width - 0.5) * 2.0 * kPi;
        const glm::dvec3 d(std::cos(lat) * std::cos(phi), std::sin(lat), std::cos(lat) * std::sin(phi));
        const std::uint8_t* px = im.pixel(x, y);
        const glm::dvec3 radiance(lin[px[0]], lin[px[1]], lin[px[2]]);
        for (int a = 0; a < 6; ++a) {
          const double w = std::max(0.0, glm::dot(d, axes[a])) * solid_angle;
          sum[a] += radiance * w;
          weight[a] += w;
        }
      }
    }
    std::array<glm::vec3, 6> out{};
    for (int a = 0; a < 6; ++a) out[std::size_t(a)] = glm::vec3(sum[a] / std::max(weight[a], 1e-12) * double(strength));
    return out;
  }

  void validate_nodes() {
    const std::size_t n = m_.nodes.size();
    parent_.assign(n, -1);
    node_ok_.assign(n, 1);
    in_loop_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& nd = m_.nodes[i];
      const std::string p = idx("nodes", i);
      for (std::size_t k = 0; k < nd.children.size(); ++k) {
        int c = nd.children[k];
        if (c < 0 || static_cast<std::size_t>(c) >= n) {
          error(p + ".children[" + std::to_string(k) + "]", "node index " + std::to_string(c) + " out of range");
        } else if (parent_[static_cast<std::size_t>(c)] >= 0 || static_cast<std::size_t>(c) == i) {
          if (static_cast<std::size_t>(c) != i && parent_[static_cast<std::size_t>(c)] != static_cast<int>(i)) {
            error(idx("nodes", static_cast<std::size_t>(c)), "node has more than one parent (nodes " +
                                                              std::to_string(parent_[static_cast<std::size_t>(c)]) + " and " + std::to_string(i) + ")");
          } else if (static_cast<std::size_t>(c) == i) {
            in_loop_[i] = 1;
          }
        } else {
          parent_[static_cast<std::size_t>(c)] = static_cast<int>(i);
        }
      }
      auto finite_vec = [&](const std::vector<double>& v, std::size_t want, const char* field) {
        if (v.empty()) return true;
        if (v.size() != want) {
          error(p + "." + field, "expected " + std::to_string(want) + " numbers, got " + std::to_string(v.size()));
          return false;
        }
        bool ok = true;
        for (std::size_t k = 0; k < v.size(); ++k) {
          if (!std::isfinite(v[k])) error(p + "." + field + "[" + std::to_string(k) + "]", "value " + fmt(v[k]) + " is not finite"), ok = false;
        }
        return ok;
      };
      finite_vec(nd.translation, 3, "translation");
      finite_vec(nd.scale, 3, "scale");
      if (finite_vec(nd.rotation, 4, "rotation") && nd.rotation.size() == 4) {
        double len = std::sqrt(nd.rotation[0] * nd.rotation[0] + nd.rotation[1] * nd.rotation[1] +
                               nd.rotation[2] * nd.rotation[2] + nd.rotation[3] * nd.rotation[3]);
        if (std::abs(len - 1.0) > 1e-3) {
          error(p + ".rotation", "quaternion not unit length (|q| = " + fmt(len) + ")");
        } else if (std::abs(len - 1.0) > 1e-6) {
          repair(p + ".rotation", "quaternion |q| = " + fmt(len) + " renormalised (export rounding)");
        }
      }
      if (finite_vec(nd.matrix, 16, "matrix") && nd.matrix.size() == 16) {
        std::string why;
        glm::vec3 t, s;
        glm::quat r;
        if (!decompose(nd.matrix, t, r, s, why)) error(p + ".matrix", "matrix is not decomposable to TRS (" + why + ")");
      }
      if (nd.mesh >= 0 && static_cast<std::size_t>(nd.mesh) >= m_.meshes.size()) error(p + ".mesh", "index out of range");
      if (nd.skin >= 0 && static_cast<std::size_t>(nd.skin) >= m_.skins.size()) error(p + ".skin", "index out of range");
      if (nd.camera >= 0 && static_cast<std::size_t>(nd.camera) >= m_.cameras.size()) error(p + ".camera", "index out of range");
      if (nd.skin >= 0 && nd.mesh < 0) error(p + ".skin", "a skin needs a mesh on the same node");
      int light = node_light(i);
      if (light < -1 || light >= static_cast<int>(m_.lights.size())) error(p + ".extensions.KHR_lights_punctual.light", "index out of range");
      for (double w : nd.weights) {
        if (!std::isfinite(w)) error(p + ".weights", "non-finite morph weight");
      }
    }
    // Loops: walking up the parents from any node must end within n steps.
    for (std::size_t i = 0; i < n; ++i) {
      int cur = static_cast<int>(i);
      std::size_t steps = 0;
      while (cur >= 0 && steps <= n) cur = parent_[static_cast<std::size_t>(cur)], ++steps;
      if (cur >= 0 || in_loop_[i]) {
        in_loop_[i] = 1;
        error(idx("nodes", i), "node is part of a node loop (a node is its own ancestor)");
      }
    }
  }

  int node_light(std::size_t i) const {
    const auto& ext = m_.nodes[i].extensions;
    auto it = ext.find("KHR_lights_punctual");
    if (it == ext.end() || !it->second.IsObject() || !it->second.Has("light")) return -1;
    const auto& l = it->second.Get("light");
    if (!l.IsNumber() && !l.IsInt()) return -2;
    return static_cast<int>(l.GetNumberAsInt());
  }

  static bool decompose(const std::vector<double>& mm, glm::vec3& t, glm::quat& r, glm::vec3& s, std::string& why) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < 4; ++k) m[c][k] = mm[std::size_t(c * 4 + k)];
    }
    if (std::abs(m[0][3]) > 1e-6 || std::abs(m[1][3]) > 1e-6 || std::abs(m[2][3]) > 1e-6 || std::abs(m[3][3] - 1.0) > 1e-6) {
      why = "last row must be 0 0 0 1";
      return false;
    }
    t = glm::vec3(m[3]);
    glm::dvec3 cols[3] = {glm::dvec3(m[0]), glm::dvec3(m[1]), glm::dvec3(m[2])};
    glm::dvec3 sc(glm::length(cols[0]), glm::length(cols[1]), glm::length(cols[2]));
    if (sc.x < 1e-12 || sc.y < 1e-12 || sc.z < 1e-12) {
      why = "zero scale axis";
      return false;
    }
    double det = glm::determinant(glm::dmat3(cols[0], cols[1], cols[2]));
    if (det < 0) sc.x = -sc.x;
    glm::dmat3 rot(cols[0] / sc.x, cols[1] / sc.y, cols[2] / sc.z);
    // Shear: the normalised axes must be orthogonal.
    if (std::abs(glm::dot(rot[0], rot[1])) > 1e-4 || std::abs(glm::dot(rot[0], rot[2])) > 1e-4 ||
        std::abs(glm::dot(rot[1], rot[2])) > 1e-4) {
      why = "axes are not orthogonal (shear)";
      return false;
    }
    s = glm::vec3(sc);
    r = glm::normalize(glm::quat(glm::quat_cast(rot)));
    return true;
  }

  // Joint counts of the skins of the nodes that instance mesh `mesh` (for JOINTS_n range checks).
  int max_joint_count(std::size_t mesh) const {
    int count = -1;
    for (const auto& nd : m_.nodes) {
      if (nd.mesh == static_cast<int>(mesh) && nd.skin >= 0 && static_cast<std::size_t>(nd.skin) < m_.skins.size()) {
        int jc = static_cast<int>(m_.skins[static_cast<std::size_t>(nd.skin)].joints.size());
        count = count < 0 ? jc : std::min(count, jc);
      }
    }
    return count;
  }

  void validate_mesh(std::size_t mi) {
    const auto& mesh = m_.meshes[mi];
    const std::string mp = idx("meshes", mi);
    if (mesh.primitives.empty()) error(mp + ".primitives", "a mesh needs at least one primitive");
    std::size_t targets0 = 0;
    for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const auto& prim = mesh.primitives[pi];
      const std::string pp = mp + idx(".primitives", pi);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1) {
        error(pp + ".mode", "primitive mode " + std::to_string(prim.mode) + " (points/lines) is not supported; only triangles");
      }
      auto pos_it = prim.attributes.find("POSITION");
      std::size_t vcount = 0;
      if (pos_it == prim.attributes.end()) {
        error(pp + ".attributes", "POSITION is required");
      } else if (use_accessor(pos_it->second, pp + ".attributes.POSITION", {TINYGLTF_TYPE_VEC3}, {})) {
        vcount = m_.accessors[static_cast<std::size_t>(pos_it->second)].count;
      } else {
        vcount = 0;
      }
      for (const auto& [name, acc] : prim.attributes) {
        const std::string ap = pp + ".attributes." + name;
        if (acc >= 0 && static_cast<std::size_t>(acc) < m_.accessors.size() && vcount &&
            m_.accessors[static_cast<std::size_t>(acc)].count != vcount) {
          error(ap, "has " + std::to_string(m_.accessors[static_cast<std::size_t>(acc)].count) + " elements but POSITION has " + std::to_string(vcount));
          continue;
        }
        if (name == "NORMAL") {
          if (auto* d = use_accessor(acc, ap, {TINYGLTF_TYPE_VEC3}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT})) {
            check_unit_vectors(*d, 3, 3, ap);
          }
        } else if (name == "TANGENT") {
          if (auto* d = use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT})) {
            check_unit_vectors(*d, 4, 3, ap);
            for (std::size_t e = 0; e < d->size() / 4; ++e) {
              double w = (*d)[e * 4 + 3];
              if (w != 1.0 && w != -1.0) {
                repair(ap, "element " + std::to_string(e) + " has w = " + fmt(w) + " (must be +-1): set to " + (w < 0 ? "-1" : "+1"));
              }
            }
          }
        } else if (name.rfind("TEXCOORD_", 0) == 0) {
          use_accessor(acc, ap, {TINYGLTF_TYPE_VEC2}, {});
        } else if (name.rfind("COLOR_", 0) == 0) {
          if (auto* d = use_accessor(acc, ap, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                                     {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT})) {
            for (std::size_t e = 0; e < d->size(); ++e) {
              if ((*d)[e] < 0.0 || (*d)[e] > 1.0) {
                repair(ap, "component " + std::to_string(e) + " = " + fmt((*d)[e]) + " outside 0..1: clamped");
              }
            }
          }
        } else if (name.rfind("JOINTS_", 0) == 0) {
          auto* d = use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
          std::string wname = "WEIGHTS_" + name.substr(7);
          auto wit = prim.attributes.find(wname);
          if (wit == prim.attributes.end()) {
            error(ap, "has no matching " + wname);
          } else if (d) {
            check_joints(prim, mi, name, *d, ap);
          }
          if (name != "JOINTS_0") error(ap, "more than 4 joint influences per vertex are not supported");
        } else if (name.rfind("WEIGHTS_", 0) == 0) {
          if (auto* d = use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT})) {
            for (std::size_t e = 0; e < d->size(); ++e) {
              if ((*d)[e] < 0) error(ap, "element " + std::to_string(e / 4) + " (component " + std::to_string(e % 4) + ") has negative weight " + fmt((*d)[e]));
            }
          }
        } else if (name == "POSITION") {
        } else if (!name.empty() && name[0] == '_') {
          // application-specific attribute: ignored
        } else {
          error(ap, "unknown attribute semantic");
        }
      }
      check_weight_sums(prim, pp);
      if (prim.indices >= 0) {
        if (auto* d = use_accessor(prim.indices, pp + ".indices", {TINYGLTF_TYPE_SCALAR},
                                   {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT})) {
          const int ct = m_.accessors[static_cast<std::size_t>(prim.indices)].componentType;
          const double restart = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0 : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 65535.0 : 4294967295.0;
          for (std::size_t e = 0; e < d->size(); ++e) {
            if ((*d)[e] == restart) {
              error(pp + ".indices", "element " + std::to_string(e) + " is the primitive restart value " + fmt(restart));
            } else if (vcount && (*d)[e] >= double(vcount)) {
              error(pp + ".indices", "element " + std::to_string(e) + " has value " + fmt((*d)[e]) + " but there are only " + std::to_string(vcount) + " vertices");
            }
          }
          if (prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) {
            if (d->size() % 3) error(pp + ".indices", "count " + std::to_string(d->size()) + " is not a multiple of 3");
            std::size_t degenerate = 0;
            for (std::size_t e = 0; e + 2 < d->size(); e += 3) {
              if ((*d)[e] == (*d)[e + 1] || (*d)[e] == (*d)[e + 2] || (*d)[e + 1] == (*d)[e + 2]) ++degenerate;
            }
            if (degenerate) repair(pp + ".indices", std::to_string(degenerate) + " degenerate triangle(s) of " + std::to_string(d->size() / 3) + " dropped");
          }
        }
      } else if ((prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) && vcount % 3) {
        error(pp + ".attributes.POSITION", "non-indexed triangles need a vertex count that is a multiple of 3");
      }
      if (prim.material >= 0 && static_cast<std::size_t>(prim.material) >= m_.materials.size()) {
        error(pp + ".material", "index out of range");
      }
      if (pi == 0) targets0 = prim.targets.size();
      else if (prim.targets.size() != targets0) error(pp + ".targets", "all primitives of a mesh need the same number of morph targets");
      if (prim.targets.size() > std::size_t(shadergen::kMaxMorphTargets)) {
        error(pp + ".targets", std::to_string(prim.targets.size()) + " morph targets; at most " + std::to_string(shadergen::kMaxMorphTargets) + " are supported");
      }
      for (std::size_t ti = 0; ti < prim.targets.size(); ++ti) {
        for (const auto& [name, acc] : prim.targets[ti]) {
          const std::string tp = pp + idx(".targets", ti) + "." + name;
          if (name != "POSITION" && name != "NORMAL" && name != "TANGENT") {
            error(tp, "unsupported morph target attribute");
          } else if (use_accessor(acc, tp, {TINYGLTF_TYPE_VEC3}, {}) && vcount &&
                     m_.accessors[static_cast<std::size_t>(acc)].count != vcount) {
            error(tp, "element count differs from POSITION");
          }
        }
      }
    }
    if (!mesh.weights.empty() && mesh.weights.size() != targets0) error(mp + ".weights", "count differs from the number of morph targets");
  }

  // Unit-length check (tolerance as the Khronos validator's order of magnitude, loose enough for
  // quantised data): slightly off is renormalised, clearly wrong is an error.
  void check_unit_vectors(const std::vector<double>& d, std::size_t stride, std::size_t n, const std::string& path) {
    for (std::size_t e = 0; e + stride <= d.size(); e += stride) {
      double len = 0;
      for (std::size_t c = 0; c < n; ++c) len += d[e + c] * d[e + c];
      len = std::sqrt(len);
      if (std::abs(len - 1.0) > 0.01) {
        error(path, "vector at element " + std::to_string(e / stride) + " is not unit length (|v| = " + fmt(len) + ")");
      }
    }
  }

  void check_joints(const tinygltf::Primitive& prim, std::size_t mi, const std::string& jname, const std::vector<double>& joints,
                    const std::string& ap) {
    const int jc = max_joint_count(mi);
    const auto wit = prim.attributes.find("WEIGHTS_" + jname.substr(7));
    const std::vector<double>* weights =
        (wit != prim.attributes.end() && wit->second >= 0 && static_cast<std::size_t>(wit->second) < accessor_ok_.size() &&
         accessor_ok_[static_cast<std::size_t>(wit->second)])
            ? &accessor_cache_[static_cast<std::size_t>(wit->second)]
            : nullptr;
    // Every joint set of this vertex, to find duplicates across JOINTS_0 / JOINTS_1.
    for (std::size_t e = 0; e < joints.size(); ++e) {
      const std::size_t v = e / 4;
      const double j = joints[e];
      const double w = weights && weights->size() == joints.size() ? (*weights)[e] : 1.0;
      if (jc >= 0 && j >= jc) {
        error(ap, "element " + std::to_string(v) + " (component " + std::to_string(e % 4) + ") has joint " + fmt(j) +
                      " but the skin has only " + std::to_string(jc) + " joints");
        continue;
      }
      if (w == 0.0) continue;
      // Duplicate: the same joint used earlier for this vertex with non-zero weight.
      for (const auto& [other, acc] : prim.attributes) {
        if (other.rfind("JOINTS_", 0) != 0 || other > jname || acc < 0 || static_cast<std::size_t>(acc) >= accessor_ok_.size() ||
            !accessor_ok_[static_cast<std::size_t>(acc)]) {
          continue;
        }
        const auto& oj = accessor_cache_[static_cast<std::size_t>(acc)];
        const std::size_t limit = other == jname ? e % 4 : 4;
        for (std::size_t c = 0; c < limit && v * 4 + c < oj.size(); ++c) {
          if (oj[v * 4 + c] == j) {
            error(ap, "element " + std::to_string(v) + " (component " + std::to_string(e % 4) + ") repeats joint " + fmt(j) + " already used by this vertex");
          }
        }
      }
    }
  }

  void check_weight_sums(const tinygltf::Primitive& prim, const std::string& pp) {
    std::vector<const std::vector<double>*> sets;
    std::vector<std::string> names;
    for (const auto& [name, acc] : prim.attributes) {
      if (name.rfind("WEIGHTS_", 0) == 0 && acc >= 0 && static_cast<std::size_t>(acc) < accessor_ok_.size() &&
          accessor_ok_[static_cast<std::size_t>(acc)]) {
        sets.push_back(&accessor_cache_[static_cast<std::size_t>(acc)]);
        names.push_back(name);
      }
    }
    if (sets.empty()) return;
    const std::size_t verts = sets[0]->size() / 4;
    for (std::size_t v = 0; v < verts; ++v) {
      double sum = 0;
      for (const auto* s : sets) {
        for (std::size_t c = 0; c < 4 && v * 4 + c < s->size(); ++c) sum += (*s)[v * 4 + c];
      }
      bool negative = false;
      for (const auto* st : sets) {
        for (std::size_t c = 0; c < 4 && v * 4 + c < st->size(); ++c) negative = negative || (*st)[v * 4 + c] < 0;
      }
      if (negative) {  // the sum of a set with a negative weight is meaningless: no repair possible
        for (const auto& n : names) error(pp + ".attributes." + n, "weights of element " + std::to_string(v) + " are not normalised (a weight is negative)");
        continue;
      }
      const bool total_off = std::abs(sum - 1.0) > 2e-3 * double(sets.size() * 4);
      for (std::size_t k = 0; k < sets.size(); ++k) {
        double own = 0;
        for (std::size_t c = 0; c < 4 && v * 4 + c < sets[k]->size(); ++c) own += (*sets[k])[v * 4 + c];
        // One set alone above 1 is wrong whatever the other sets hold.
        if (total_off || own > 1.0 + 8e-3) {
          repair(pp + ".attributes." + names[k], "weights of element " + std::to_string(v) + " sum to " + fmt(total_off ? sum : own) +
                                                  ": renormalised to 1");
        }
      }
    }
  }

  void validate_skin(std::size_t si) {
    const auto& skin = m_.skins[si];
    const std::string p = idx("skins", si);
    if (skin.joints.empty()) error(p + ".joints", "a skin needs at least one joint");
    if (skin.joints.size() > std::size_t(shadergen::kMaxSkinJoints)) {
      error(p + ".joints", std::to_string(skin.joints.size()) + " joints; at most " + std::to_string(shadergen::kMaxSkinJoints) + " are supported");
    }
    for (std::size_t k = 0; k < skin.joints.size(); ++k) {
      if (skin.joints[k] < 0 || static_cast<std::size_t>(skin.joints[k]) >= m_.nodes.size()) error(p + idx(".joints", k), "node index out of range");
    }
    if (skin.inverseBindMatrices >= 0) {
      if (auto* d = use_accessor(skin.inverseBindMatrices, p + ".inverseBindMatrices", {TINYGLTF_TYPE_MAT4}, {TINYGLTF_COMPONENT_TYPE_FLOAT})) {
        if (d->size() / 16 < skin.joints.size()) error(p + ".inverseBindMatrices", "fewer matrices than joints");
        for (std::size_t mtx = 0; mtx < d->size() / 16; ++mtx) {
          for (int r = 0; r < 4; ++r) {
            const double v = (*d)[mtx * 16 + std::size_t(r) * 4 + 3];
            const double want = r == 3 ? 1.0 : 0.0;
            if (v != want) {
              error(p + ".inverseBindMatrices", "matrix " + std::to_string(mtx) + " element " + std::to_string(r * 4 + 3) + " is " + fmt(v) +
                                                    " (the last row of an affine matrix must be 0 0 0 1)");
            }
          }
        }
      }
    }
  }

  void validate_animation(std::size_t ai) {
    const auto& anim = m_.animations[ai];
    const std::string p = idx("animations", ai);
    for (std::size_t si = 0; si < anim.samplers.size(); ++si) {
      const auto& s = anim.samplers[si];
      const std::string sp = p + idx(".samplers", si);
      if (s.interpolation != "LINEAR" && s.interpolation != "STEP" && s.interpolation != "CUBICSPLINE" && !s.interpolation.empty()) {
        error(sp + ".interpolation", "unknown interpolation \"" + s.interpolation + "\"");
      }
      auto* in = use_accessor(s.input, sp + ".input", {TINYGLTF_TYPE_SCALAR}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
      use_accessor(s.output, sp + ".output", {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, {});
      if (!in) continue;
      for (std::size_t k = 0; k < in->size(); ++k) {
        if ((*in)[k] < 0) error(sp + ".input", "key " + std::to_string(k) + " has negative time " + fmt((*in)[k]));
        if (k > 0 && !((*in)[k] > (*in)[k - 1])) {
          error(sp + ".input", "key " + std::to_string(k) + " time " + fmt((*in)[k]) + " is not greater than the previous " + fmt((*in)[k - 1]));
        }
      }
      if (s.interpolation == "CUBICSPLINE" && in->size() < 2) {
        error(sp + ".input", "CUBICSPLINE needs at least 2 keys, got " + std::to_string(in->size()));
      }
    }
    for (std::size_t ci = 0; ci < anim.channels.size(); ++ci) {
      const auto& ch = anim.channels[ci];
      const std::string cp = p + idx(".channels", ci);
      if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size()) {
        error(cp + ".sampler", "index out of range");
        continue;
      }
      if (ch.target_node < 0 || static_cast<std::size_t>(ch.target_node) >= m_.nodes.size()) {
        error(cp + ".target.node", "missing or out of range");
        continue;
      }
      const auto& s = anim.samplers[static_cast<std::size_t>(ch.sampler)];
      const std::string sp = p + idx(".samplers", static_cast<std::size_t>(ch.sampler));
      const bool cubic = s.interpolation == "CUBICSPLINE";
      if (s.input < 0 || s.output < 0 || static_cast<std::size_t>(s.input) >= m_.accessors.size() ||
          static_cast<std::size_t>(s.output) >= m_.accessors.size() || !accessor_ok_[static_cast<std::size_t>(s.input)] ||
          !accessor_ok_[static_cast<std::size_t>(s.output)]) {
        continue;
      }
      const auto keys = m_.accessors[static_cast<std::size_t>(s.input)].count;
      const auto& oa = m_.accessors[static_cast<std::size_t>(s.output)];
      const auto& out = accessor_cache_[static_cast<std::size_t>(s.output)];
      int comps = 0;
      if (ch.target_path == "translation" || ch.target_path == "scale") {
        comps = 3;
        if (oa.type != TINYGLTF_TYPE_VEC3) error(sp + ".output", "must be VEC3 for " + ch.target_path);
      } else if (ch.target_path == "rotation") {
        comps = 4;
        if (oa.type != TINYGLTF_TYPE_VEC4) error(sp + ".output", "must be VEC4 for rotation");
      } else if (ch.target_path == "weights") {
        const auto& nd = m_.nodes[static_cast<std::size_t>(ch.target_node)];
        if (nd.mesh < 0 || static_cast<std::size_t>(nd.mesh) >= m_.meshes.size() || m_.meshes[static_cast<std::size_t>(nd.mesh)].primitives.empty() ||
            m_.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].targets.empty()) {
          error(cp + ".target", "weights animation on a node without morph targets");
          continue;
        }
        comps = static_cast<int>(m_.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].targets.size());
        if (oa.type != TINYGLTF_TYPE_SCALAR) error(sp + ".output", "must be SCALAR for weights");
      } else {
        error(cp + ".target.path", "unsupported path \"" + ch.target_path + "\"");
        continue;
      }
      const std::size_t per_key = std::size_t(comps) * (cubic ? 3 : 1);
      if (oa.count * std::size_t(type_components(oa.type)) != keys * per_key) {
        error(sp + ".output", "has " + std::to_string(oa.count) + " elements; " + std::to_string(keys) + " keys need " +
                                  std::to_string(keys * per_key / std::size_t(std::max(1, type_components(oa.type)))));
        continue;
      }
      if (comps == 4 && oa.type == TINYGLTF_TYPE_VEC4) {
        for (std::size_t k = 0; k < keys; ++k) {
          const std::size_t base = k * per_key + (cubic ? 4 : 0);  // values only; tangents need not be unit
          double len = std::sqrt(out[base] * out[base] + out[base + 1] * out[base + 1] + out[base + 2] * out[base + 2] + out[base + 3] * out[base + 3]);
          if (std::abs(len - 1.0) > 1e-3) {
            error(cp + ".sampler", "rotation key " + std::to_string(k) + " (output elements " + std::to_string(base / 4 * 4) + ".." +
                                       std::to_string(base + 3) + ") is not a unit quaternion (|q| = " + fmt(len) + ")");
          }
        }
      }
    }
  }

  void texture_ref(int index, int texcoord, const std::string& p) {
    if (index < 0) return;
    if (static_cast<std::size_t>(index) >= m_.textures.size()) error(p + ".index", "texture index out of range");
    if (texcoord < 0 || texcoord > 1) error(p + ".texCoord", "only TEXCOORD_0 and TEXCOORD_1 are supported");
  }

  void validate_material(std::size_t i) {
    const auto& mat = m_.materials[i];
    const std::string p = idx("materials", i);
    const auto& pbr = mat.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) error(p + ".pbrMetallicRoughness.baseColorFactor", "expected 4 numbers");
    for (double v : pbr.baseColorFactor) {
      if (!(v >= 0 && v <= 1)) error(p + ".pbrMetallicRoughness.baseColorFactor", "components must be in 0..1");
    }
    if (!(pbr.metallicFactor >= 0 && pbr.metallicFactor <= 1)) error(p + ".pbrMetallicRoughness.metallicFactor", "must be in 0..1");
    if (!(pbr.roughnessFactor >= 0 && pbr.roughnessFactor <= 1)) error(p + ".pbrMetallicRoughness.roughnessFactor", "must be in 0..1");
    if (mat.emissiveFactor.size() != 3) error(p + ".emissiveFactor", "expected 3 numbers");
    for (double v : mat.emissiveFactor) {
      if (!(v >= 0 && v <= 1)) error(p + ".emissiveFactor", "components must be in 0..1");
    }
    if (mat.alphaMode != "OPAQUE" && mat.alphaMode != "MASK" && mat.alphaMode != "BLEND") error(p + ".alphaMode", "unknown alpha mode \"" + mat.alphaMode + "\"");
    if (!(mat.alphaCutoff >= 0)) error(p + ".alphaCutoff", "must be >= 0");
    texture_ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, p + ".pbrMetallicRoughness.baseColorTexture");
    texture_ref(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, p + ".pbrMetallicRoughness.metallicRoughnessTexture");
    texture_ref(mat.normalTexture.index, mat.normalTexture.texCoord, p + ".normalTexture");
    texture_ref(mat.occlusionTexture.index, mat.occlusionTexture.texCoord, p + ".occlusionTexture");
    texture_ref(mat.emissiveTexture.index, mat.emissiveTexture.texCoord, p + ".emissiveTexture");
  }

  // ---------------------------------------------------------------- conversion
  static int gl_filter(int f, int fallback) { return f > 0 ? f : fallback; }

  glm::mat3 uv_transform(const tinygltf::ExtensionMap& ext, int& texcoord, bool& has) const {
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

  Material convert_material(std::size_t i, std::vector<int>& texture_srgb) {
    const auto& mat = m_.materials[i];
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
    auto ov = cfg_.materials.find(out.name);
    if (ov != cfg_.materials.end() && ov->second.shading) {
      const std::string& s = *ov->second.shading;
      out.shading = s == "unlit" ? shadergen::ShadingModel::Unlit
                    : s == "flat" ? shadergen::ShadingModel::Flat
                    : s == "gouraud" ? shadergen::ShadingModel::Gouraud
                    : s == "blinn-phong" ? shadergen::ShadingModel::BlinnPhong
                                         : shadergen::ShadingModel::PbrMetallicRoughness;
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
        repair(idx("materials", i), "texture " + std::to_string(info.index) + " is used both as colour and as data; decoded as sRGB colour");
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

  // Flattens an accessor to floats for a vertex attribute (with the repairs the validator announced).
  std::vector<float> attribute(int acc, int comps_out, bool clamp01 = false) {
    const auto& a = m_.accessors[static_cast<std::size_t>(acc)];
    const auto& d = accessor_cache_[static_cast<std::size_t>(acc)];
    const int nc = type_components(a.type);
    std::vector<float> out(a.count * std::size_t(comps_out), 1.0f);
    for (std::size_t e = 0; e < a.count; ++e) {
      for (int c = 0; c < std::min(nc, comps_out); ++c) {
        double v = d[e * std::size_t(nc) + std::size_t(c)];
        if (clamp01) v = std::clamp(v, 0.0, 1.0);
        out[e * std::size_t(comps_out) + std::size_t(c)] = static_cast<float>(v);
      }
    }
    return out;
  }

  struct RawPrimitive {
    std::map<std::pair<int, int>, std::pair<int, std::vector<float>>> attrs;  // (semantic, index) -> (components, data)
    std::vector<std::uint32_t> indices;
    std::size_t vcount = 0;
  };

  Primitive convert_primitive(std::size_t mi, std::size_t pi, const Material& material, int material_index) {
    const auto& prim = m_.meshes[mi].primitives[pi];
    const std::string pp = idx("meshes", mi) + idx(".primitives", pi);
    RawPrimitive raw;
    auto add = [&](AttributeSemantic s, int index, int comps, std::vector<float> data) {
      raw.attrs[{int(s), index}] = {comps, std::move(data)};
    };
    const int pos = prim.attributes.at("POSITION");
    raw.vcount = m_.accessors[static_cast<std::size_t>(pos)].count;
    add(AttributeSemantic::Position, -1, 3, attribute(pos, 3));
    auto has = [&](const char* n) { return prim.attributes.count(n) > 0; };
    if (has("NORMAL")) {
      auto n = attribute(prim.attributes.at("NORMAL"), 3);
      for (std::size_t v = 0; v < raw.vcount; ++v) {
        glm::vec3 x(n[v * 3], n[v * 3 + 1], n[v * 3 + 2]);
        x = glm::normalize(x);
        n[v * 3] = x.x, n[v * 3 + 1] = x.y, n[v * 3 + 2] = x.z;
      }
      add(AttributeSemantic::Normal, -1, 3, std::move(n));
    }
    if (has("TANGENT") && material.texture[int(TextureSlot::Normal)] >= 0) {
      auto t = attribute(prim.attributes.at("TANGENT"), 4);
      for (std::size_t v = 0; v < raw.vcount; ++v) t[v * 4 + 3] = t[v * 4 + 3] < 0 ? -1.0f : 1.0f;
      add(AttributeSemantic::Tangent, -1, 4, std::move(t));
    }
    if (has("TEXCOORD_0")) add(AttributeSemantic::TexCoord0, -1, 2, attribute(prim.attributes.at("TEXCOORD_0"), 2));
    if (has("TEXCOORD_1")) add(AttributeSemantic::TexCoord1, -1, 2, attribute(prim.attributes.at("TEXCOORD_1"), 2));
    if (has("COLOR_0")) add(AttributeSemantic::Color0, -1, 4, attribute(prim.attributes.at("COLOR_0"), 4, true));
    if (has("JOINTS_0") && has("WEIGHTS_0")) {
      add(AttributeSemantic::Joints0, -1, 4, attribute(prim.attributes.at("JOINTS_0"), 4));
      auto w = attribute(prim.attributes.at("WEIGHTS_0"), 4);
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
      add(AttributeSemantic::MorphPosition, int(ti), 3, p != t.end() ? attribute(p->second, 3) : std::vector<float>(raw.vcount * 3, 0.0f));
      auto n = t.find("NORMAL");
      if (n != t.end() && raw.attrs.count({int(AttributeSemantic::Normal), -1})) add(AttributeSemantic::MorphNormal, int(ti), 3, attribute(n->second, 3));
    }
    // Indices -> triangle list, degenerate triangles dropped.
    std::vector<std::uint32_t> src;
    if (prim.indices >= 0) {
      for (double v : accessor_cache_[static_cast<std::size_t>(prim.indices)]) src.push_back(static_cast<std::uint32_t>(v));
    } else {
      for (std::size_t v = 0; v < raw.vcount; ++v) src.push_back(static_cast<std::uint32_t>(v));
    }
    std::vector<std::uint32_t> tris;
    auto push = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      if (a != b && a != c && b != c) tris.insert(tris.end(), {a, b, c});
    };
    if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t k = 0; k + 2 < src.size(); ++k) (k % 2) ? push(src[k + 1], src[k], src[k + 2]) : push(src[k], src[k + 1], src[k + 2]);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      for (std::size_t k = 1; k + 1 < src.size(); ++k) push(src[0], src[k], src[k + 1]);
    } else {
      for (std::size_t k = 0; k + 2 < src.size(); k += 3) push(src[k], src[k + 1], src[k + 2]);
    }
    // Lit shading without NORMAL: glTF says compute flat normals, which needs unshared vertices.
    if (!raw.attrs.count({int(AttributeSemantic::Normal), -1}) && material.shading != shadergen::ShadingModel::Unlit) {
      RawPrimitive flat;
      flat.vcount = tris.size();
      for (auto& [key, val] : raw.attrs) {
        std::vector<float> d;
        d.reserve(tris.size() * std::size_t(val.first));
        for (auto v : tris) d.insert(d.end(), val.second.begin() + std::ptrdiff_t(v) * val.first, val.second.begin() + std::ptrdiff_t(v + 1) * val.first);
        flat.attrs[key] = {val.first, std::move(d)};
      }
      const auto& p = flat.attrs[{int(AttributeSemantic::Position), -1}].second;
      std::vector<float> n(tris.size() * 3);
      for (std::size_t t = 0; t < tris.size(); t += 3) {
        glm::vec3 a(p[t * 3], p[t * 3 + 1], p[t * 3 + 2]), b(p[t * 3 + 3], p[t * 3 + 4], p[t * 3 + 5]), c(p[t * 3 + 6], p[t * 3 + 7], p[t * 3 + 8]);
        glm::vec3 fn = glm::cross(b - a, c - a);
        fn = glm::length(fn) > 0 ? glm::normalize(fn) : glm::vec3(0, 0, 1);
        for (int k = 0; k < 3; ++k) n[(t + std::size_t(k)) * 3] = fn.x, n[(t + std::size_t(k)) * 3 + 1] = fn.y, n[(t + std::size_t(k)) * 3 + 2] = fn.z;
      }
      flat.attrs[{int(AttributeSemantic::Normal), -1}] = {3, std::move(n)};
      for (std::size_t k = 0; k < tris.size(); ++k) flat.indices.push_back(static_cast<std::uint32_t>(k));
      repair(pp + ".attributes", "no NORMAL for lit shading: flat normals computed (glTF 3.7.2.1)");
      raw = std::move(flat);
    } else {
      raw.indices = std::move(tris);
    }
    Primitive out;
    out.material = material_index;
    out.vertex_count = static_cast<std::uint32_t>(raw.vcount);
    out.morph_targets = static_cast<int>(prim.targets.size());
    // Interleave in map order (Position, Normal, Tangent, TexCoord0, ...; morph targets last).
    for (auto& [key, val] : raw.attrs) {
      out.layout.push_back({static_cast<AttributeSemantic>(key.first), key.second, val.first, out.stride});
      out.stride += val.first;
    }
    out.vertices.resize(raw.vcount * std::size_t(out.stride));
    for (const auto& l : out.layout) {
      const auto& d = raw.attrs[{int(l.semantic), l.index}].second;
      for (std::size_t v = 0; v < raw.vcount; ++v) {
        for (int c = 0; c < l.components; ++c) out.vertices[v * std::size_t(out.stride) + std::size_t(l.offset + c)] = d[v * std::size_t(l.components) + std::size_t(c)];
      }
    }
    out.indices = std::move(raw.indices);
    const auto& p = raw.attrs[{int(AttributeSemantic::Position), -1}].second;
    out.bounds_min = glm::vec3(std::numeric_limits<float>::max());
    out.bounds_max = glm::vec3(-std::numeric_limits<float>::max());
    for (std::size_t v = 0; v < raw.vcount; ++v) {
      glm::vec3 x(p[v * 3], p[v * 3 + 1], p[v * 3 + 2]);
      out.bounds_min = glm::min(out.bounds_min, x);
      out.bounds_max = glm::max(out.bounds_max, x);
    }
    if (raw.vcount == 0) out.bounds_min = out.bounds_max = glm::vec3(0.0f);
    return out;
  }

  Scene build() {
    Scene s;
    s.source_name = file_;
    s.config = cfg_;
    s.ambient = glm::vec3(cfg_.ambient[0], cfg_.ambient[1], cfg_.ambient[2]);
    // Textures (decoded RGBA8; colour textures flagged sRGB).
    std::vector<int> texture_srgb(m_.textures.size(), -1);
    for (std::size_t i = 0; i < m_.materials.size(); ++i) s.materials.push_back(convert_material(i, texture_srgb));
    // glTF default material for primitives without one.
    const int default_material = static_cast<int>(s.materials.size());
    {
      Material d;
      d.name = "__default";
      d.metallic = 1.0f;
      d.roughness = 1.0f;
      s.materials.push_back(d);
    }
    for (std::size_t i = 0; i < m_.textures.size(); ++i) {
      const auto& t = m_.textures[i];
      const auto& im = m_.images[static_cast<std::size_t>(t.source)];
      Texture out;
      out.name = !t.name.empty() ? t.name : im.name;
      out.width = im.width;
      out.height = im.height;
      out.srgb = texture_srgb[i] == 1;
      out.rgba.resize(std::size_t(im.width) * std::size_t(im.height) * 4);
      for (std::size_t px = 0; px < std::size_t(im.width) * std::size_t(im.height); ++px) {
        const auto* src = im.image.data() + px * std::size_t(im.component);
        std::uint8_t r = src[0], g = im.component >= 3 ? src[1] : src[0], b = im.component >= 3 ? src[2] : src[0];
        std::uint8_t a = im.component == 4 ? src[3] : im.component == 2 ? src[1] : 255;
        out.rgba[px * 4] = r, out.rgba[px * 4 + 1] = g, out.rgba[px * 4 + 2] = b, out.rgba[px * 4 + 3] = a;
      }
      if (t.sampler >= 0) {
        const auto& sm = m_.samplers[static_cast<std::size_t>(t.sampler)];
        out.min_filter = gl_filter(sm.minFilter, out.min_filter);
        out.mag_filter = gl_filter(sm.magFilter, out.mag_filter);
        out.wrap_s = sm.wrapS;
        out.wrap_t = sm.wrapT;
      }
      s.textures.push_back(std::move(out));
    }
    if (!environment_.empty()) {
      // sRGB like Blender's "sRGB" image colour space (sampling returns linear radiance);
      // mipmapped because rough surfaces read blurred levels; wraps in longitude, clamps at the poles.
      Texture env;
      env.name = "environment:" + environment_name_;
      env.width = environment_.width;
      env.height = environment_.height;
      env.rgba = environment_.rgba;
      env.srgb = true;
      env.wrap_s = 0x2901 /*REPEAT*/;
      env.wrap_t = 0x812F /*CLAMP_TO_EDGE*/;
      s.environment.texture = static_cast<int>(s.textures.size());
      s.environment.strength = environment_strength_;
      s.environment.irradiance = ambient_cube(environment_, environment_strength_);
      s.textures.push_back(std::move(env));
    }
    // Meshes.
    for (std::size_t mi = 0; mi < m_.meshes.size(); ++mi) {
      const auto& mesh = m_.meshes[mi];
      Mesh out;
      out.name = mesh.name.empty() ? "mesh" + std::to_string(mi) : mesh.name;
      for (double w : mesh.weights) out.weights.push_back(static_cast<float>(w));
      for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
        const int mat = mesh.primitives[pi].material >= 0 ? mesh.primitives[pi].material : default_material;
        out.primitives.push_back(convert_primitive(mi, pi, s.materials[static_cast<std::size_t>(mat)], mat));
      }
      if (out.weights.empty() && !out.primitives.empty()) out.weights.assign(static_cast<std::size_t>(out.primitives[0].morph_targets), 0.0f);
      s.meshes.push_back(std::move(out));
    }
    for (std::size_t i = 0; i < m_.cameras.size(); ++i) {
      const auto& c = m_.cameras[i];
      Camera out;
      out.name = c.name.empty() ? "camera" + std::to_string(i) : c.name;
      out.perspective = c.type == "perspective";
      if (out.perspective) {
        out.yfov = static_cast<float>(c.perspective.yfov), out.znear = static_cast<float>(c.perspective.znear), out.zfar = static_cast<float>(c.perspective.zfar);
      } else {
        out.xmag = static_cast<float>(c.orthographic.xmag), out.ymag = static_cast<float>(c.orthographic.ymag);
        out.znear = static_cast<float>(c.orthographic.znear), out.zfar = static_cast<float>(c.orthographic.zfar);
      }
      s.cameras.push_back(out);
    }
    for (std::size_t i = 0; i < m_.lights.size(); ++i) {
      const auto& l = m_.lights[i];
      Light out;
      out.name = l.name.empty() ? "light" + std::to_string(i) : l.name;
      out.type = l.type == "point" ? LightType::Point : l.type == "spot" ? LightType::Spot : LightType::Directional;
      if (l.color.size() == 3) out.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
      out.intensity = static_cast<float>(l.intensity);
      out.range = static_cast<float>(l.range);
      out.inner_cone = static_cast<float>(l.spot.innerConeAngle);
      out.outer_cone = static_cast<float>(l.spot.outerConeAngle);
      s.lights.push_back(out);
    }
    for (std::size_t i = 0; i < m_.skins.size(); ++i) {
      const auto& k = m_.skins[i];
      Skin out;
      out.name = k.name;
      out.joints = k.joints;
      for (std::size_t j = 0; j < k.joints.size(); ++j) {
        glm::mat4 m(1.0f);
        if (k.inverseBindMatrices >= 0) {
          const auto& d = accessor_cache_[static_cast<std::size_t>(k.inverseBindMatrices)];
          for (int c = 0; c < 16; ++c) m[c / 4][c % 4] = static_cast<float>(d[j * 16 + std::size_t(c)]);
        }
        out.inverse_bind.push_back(m);
      }
      s.skins.push_back(std::move(out));
    }
    // Nodes: all of them (indices stay glTF indices); the roots are the default scene's.
    for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
      const auto& nd = m_.nodes[i];
      Node out;
      out.name = nd.name.empty() ? "node" + std::to_string(i) : nd.name;
      out.parent = parent_[i];
      out.children = nd.children;
      if (nd.matrix.size() == 16) {
        std::string why;
        decompose(nd.matrix, out.translation, out.rotation, out.scale, why);
      } else {
        if (nd.translation.size() == 3) out.translation = glm::vec3(nd.translation[0], nd.translation[1], nd.translation[2]);
        if (nd.rotation.size() == 4) out.rotation = glm::normalize(glm::quat(float(nd.rotation[3]), float(nd.rotation[0]), float(nd.rotation[1]), float(nd.rotation[2])));
        if (nd.scale.size() == 3) out.scale = glm::vec3(nd.scale[0], nd.scale[1], nd.scale[2]);
      }
      out.mesh = nd.mesh;
      out.camera = nd.camera;
      out.light = node_light(i);
      out.skin = nd.skin;
      for (double w : nd.weights) out.weights.push_back(static_cast<float>(w));
      if (out.weights.empty() && out.mesh >= 0) out.weights = s.meshes[static_cast<std::size_t>(out.mesh)].weights;
      s.nodes.push_back(std::move(out));
    }
    if (!m_.scenes.empty()) {
      s.roots = m_.scenes[static_cast<std::size_t>(m_.defaultScene >= 0 ? m_.defaultScene : 0)].nodes;
    } else {
      for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
        if (parent_[i] < 0) s.roots.push_back(static_cast<int>(i));
      }
    }
    // Animations.
    for (std::size_t ai = 0; ai < m_.animations.size(); ++ai) {
      const auto& a = m_.animations[ai];
      Animation out;
      out.name = a.name.empty() ? "animation" + std::to_string(ai) : a.name;
      out.start = std::numeric_limits<float>::max();
      out.end = 0.0f;
      std::map<std::pair<int, int>, int> sampler_for;  // (gltf sampler, components) -> ours
      for (const auto& ch : a.channels) {
        const auto& gs = a.samplers[static_cast<std::size_t>(ch.sampler)];
        TargetPath path = ch.target_path == "translation" ? TargetPath::Translation
                          : ch.target_path == "rotation"  ? TargetPath::Rotation
                          : ch.target_path == "scale"     ? TargetPath::Scale
                                                          : TargetPath::Weights;
        int comps = path == TargetPath::Rotation ? 4 : path == TargetPath::Weights
                                                           ? static_cast<int>(m_.meshes[static_cast<std::size_t>(m_.nodes[static_cast<std::size_t>(ch.target_node)].mesh)].primitives[0].targets.size())
                                                           : 3;
        auto key = std::make_pair(ch.sampler, comps);
        if (!sampler_for.count(key)) {
          AnimSampler sm;
          sm.interpolation = gs.interpolation == "STEP" ? Interpolation::Step : gs.interpolation == "CUBICSPLINE" ? Interpolation::CubicSpline : Interpolation::Linear;
          sm.components = comps;
          for (double v : accessor_cache_[static_cast<std::size_t>(gs.input)]) sm.input.push_back(static_cast<float>(v));
          for (double v : accessor_cache_[static_cast<std::size_t>(gs.output)]) sm.output.push_back(static_cast<float>(v));
          out.start = std::min(out.start, sm.input.front());
          out.end = std::max(out.end, sm.input.back());
          sampler_for[key] = static_cast<int>(out.samplers.size());
          out.samplers.push_back(std::move(sm));
        }
        out.channels.push_back({sampler_for[key], ch.target_node, path});
      }
      if (out.samplers.empty()) out.start = 0.0f;
      s.animations.push_back(std::move(out));
    }
    resolve_config(s, cfg_, file_);
    // Groups are checked before programs exist: members need the vertex_alpha variant.
    plan_ = plan_groups(s, cfg_.groups, opt_.propose_groups, file_);
    for (const auto& g : plan_.groups) {
      for (const auto& m : g.members) group_members_.insert(s.find_node(m));
    }
    generate_programs(s);
    attach_groups(s, plan_);
    return s;
  }

  // ---------------------------------------------------------------- programs
  // Nodes whose world transform can change at runtime (animated themselves or below an animated node).
  std::vector<char> dynamic_nodes(const Scene& s) const {
    std::vector<char> animated(s.nodes.size(), 0), dyn(s.nodes.size(), 0);
    for (const auto& a : s.animations) {
      for (const auto& ch : a.channels) animated[static_cast<std::size_t>(ch.node)] = 1;
    }
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      for (int n = static_cast<int>(i); n >= 0; n = s.nodes[static_cast<std::size_t>(n)].parent) {
        if (animated[static_cast<std::size_t>(n)]) dyn[i] = 1;
      }
    }
    return dyn;
  }

  void generate_programs(Scene& s) {
    // Scene-wide light set: light nodes reachable from the roots.
    std::vector<int> light_nodes;
    {
      std::vector<int> stack(s.roots.rbegin(), s.roots.rend());
      while (!stack.empty()) {
        int n = stack.back();
        stack.pop_back();
        if (s.nodes[static_cast<std::size_t>(n)].light >= 0) light_nodes.push_back(n);
        const auto& ch = s.nodes[static_cast<std::size_t>(n)].children;
        stack.insert(stack.end(), ch.rbegin(), ch.rend());
      }
    }
    std::stable_sort(light_nodes.begin(), light_nodes.end(), [&](int a, int b) {
      return int(s.lights[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(a)].light)].type) <
             int(s.lights[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(b)].light)].type);
    });
    shadergen::LightCounts lights;
    for (int n : light_nodes) {
      switch (s.lights[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(n)].light)].type) {
        case LightType::Directional: ++lights.directional; break;
        case LightType::Point: ++lights.point; break;
        case LightType::Spot: ++lights.spot; break;
      }
    }
    if (lights.total() > shadergen::kMaxLights) {
      throw SceneError(file_ + ": extensions.KHR_lights_punctual: the scene uses " + std::to_string(lights.total()) +
                       " lights; at most " + std::to_string(shadergen::kMaxLights) + " are supported");
    }
    std::set<int> bound_materials;
    for (const auto& b : cfg_.bindings) {
      if (b.kind == BindingKind::Emissive || b.kind == BindingKind::Color) bound_materials.insert(s.find_material(b.material));
    }
    const auto dyn = dynamic_nodes(s);
    std::map<std::string, int> cache;
    std::vector<int> stack(s.roots.rbegin(), s.roots.rend());
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      const Node& node = s.nodes[static_cast<std::size_t>(n)];
      stack.insert(stack.end(), node.children.rbegin(), node.children.rend());
      if (node.mesh < 0) continue;
      const Mesh& mesh = s.meshes[static_cast<std::size_t>(node.mesh)];
      for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
        const Primitive& prim = mesh.primitives[pi];
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
        f.vertex_alpha = group_members_.count(n) > 0;
        f = shadergen::canonical(f);
        const bool fold_material = opt_.optimize && !bound_materials.count(prim.material);
        std::string key = shadergen::program_key(f);
        if (opt_.optimize) key += fold_material ? "|mat" + std::to_string(prim.material) : "|dynmat";
        auto it = cache.find(key);
        int program = -1;
        if (it != cache.end()) {
          program = it->second;
        } else {
          ProgramEntry e;
          try {
            e.program = shadergen::generate(f);
            if (opt_.optimize) {
              shadergen::ConstantValues cv = constants(s, mat, fold_material, light_nodes, dyn);
              e.program = shadergen::optimize(e.program, cv, &e.optimize_report);
            } else {
              // Same measurements as optimize() reports, so --report compares like with like.
              auto& r = e.optimize_report;
              r.spirv_instructions_before = r.spirv_instructions_after =
                  shadergen::spirv_instruction_count(shadergen::compile_to_spirv(e.program.vertex_source, shadergen::ShaderStage::Vertex)) +
                  shadergen::spirv_instruction_count(shadergen::compile_to_spirv(e.program.fragment_source, shadergen::ShaderStage::Fragment));
              r.uniforms_before = r.uniforms_after = e.program.uniforms.size();
              r.samplers_before = r.samplers_after = e.program.samplers.size();
              r.source_bytes_before = r.source_bytes_after = e.program.vertex_source.size() + e.program.fragment_source.size();
            }
          } catch (const std::exception& ex) {
            throw SceneError(file_ + ": " + idx("meshes", static_cast<std::size_t>(node.mesh)) + idx(".primitives", pi) + " (material \"" + mat.name +
                             "\", features " + shadergen::program_key(f) + "): shader generation failed: " + ex.what());
          }
          program = static_cast<int>(s.programs.size());
          s.programs.push_back(std::move(e));
          cache[key] = program;
        }
        s.draws.push_back({n, node.mesh, static_cast<int>(pi), program});
      }
    }
  }

  // Values the scene never changes, folded into the program by shadergen::optimize().
  shadergen::ConstantValues constants(const Scene& s, const Material& m, bool fold_material, const std::vector<int>& light_nodes,
                                      const std::vector<char>& dyn) const {
    using U = shadergen::UniformSemantic;
    shadergen::ConstantValues cv;
    if (fold_material) {
      cv.set(U::BaseColorFactor, {m.base_color.r, m.base_color.g, m.base_color.b, m.base_color.a});
      cv.set(U::EmissiveFactor, {m.emissive.r, m.emissive.g, m.emissive.b});
    }
    cv.set(U::MetallicFactor, {m.metallic});
    cv.set(U::RoughnessFactor, {m.roughness});
    cv.set(U::NormalScale, {m.normal_scale});
    cv.set(U::OcclusionStrength, {m.occlusion_strength});
    cv.set(U::AlphaCutoff, {m.alpha_cutoff});
    cv.set(U::SpecularColor, {m.specular_color.r, m.specular_color.g, m.specular_color.b});
    cv.set(U::Shininess, {m.shininess});
    cv.set(U::AmbientLight, {s.ambient.r, s.ambient.g, s.ambient.b});
    cv.set(U::Exposure, {static_cast<float>(std::exp2(cfg_.exposure))});
    cv.set(U::EnvironmentIntensity, {s.environment.strength});
    for (int a = 0; a < 6; ++a) {
      const glm::vec3& e = s.environment.irradiance[std::size_t(a)];
      cv.set(U::EnvironmentIrradiance, a, {e.r, e.g, e.b});
    }
    for (int k = 0; k < 5; ++k) {
      const glm::mat3& t = m.uv_transform[std::size_t(k)];
      cv.set(U::TextureTransform, k, std::vector<float>(glm::value_ptr(t), glm::value_ptr(t) + 9));
    }
    // Lights: colour, intensity, range and cones never change at runtime; position and direction
    // come from node transforms, folded only when the light node cannot move (no animated ancestor).
    Pose rest = Pose::rest(s);
    std::vector<glm::mat4> world;
    world_matrices(s, rest, world);
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
    (void)dyn;
    return cv;
  }
};

}  // namespace

void resolve_config(const Scene& s, const SceneConfig& c, const std::string& origin) {
  auto fail = [&](std::size_t i, const std::string& field, const std::string& what) {
    throw SceneError(origin + ": scene config $.bindings[" + std::to_string(i) + "]." + field + ": " + what);
  };
  auto unique_node = [&](std::size_t i, const std::string& name, const std::string& field) {
    int found = -1, count = 0;
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      if (s.nodes[n].name == name) found = static_cast<int>(n), ++count;
    }
    if (count == 0) fail(i, field, "no node named \"" + name + "\" in the scene");
    if (count > 1) fail(i, field, "node name \"" + name + "\" is not unique in the scene");
    return found;
  };
  for (std::size_t i = 0; i < c.bindings.size(); ++i) {
    const Binding& b = c.bindings[i];
    switch (b.kind) {
      case BindingKind::Animation: {
        int a = s.find_animation(b.animation);
        if (a < 0) {
          std::string list;
          for (const auto& an : s.animations) list += (list.empty() ? "" : ", ") + an.name;
          fail(i, "animation", "no animation named \"" + b.animation + "\" (the scene has: " + (list.empty() ? "none" : list) + ")");
        }
        break;
      }
      case BindingKind::Visibility:
      case BindingKind::Text: unique_node(i, b.node, "node"); break;
      case BindingKind::Morph: {
        int n = unique_node(i, b.node, "node");
        const Node& nd = s.nodes[static_cast<std::size_t>(n)];
        if (nd.mesh < 0 || s.meshes[static_cast<std::size_t>(nd.mesh)].primitives.empty() ||
            b.morph_target >= s.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].morph_targets) {
          fail(i, "target", "node \"" + b.node + "\" has no morph target " + std::to_string(b.morph_target));
        }
        break;
      }
      case BindingKind::Emissive:
      case BindingKind::Color:
        if (s.find_material(b.material) < 0) fail(i, "material", "no material named \"" + b.material + "\" in the scene");
        break;
    }
  }
  if (!c.camera.empty()) {
    bool ok = false;
    for (const auto& n : s.nodes) ok = ok || (n.camera >= 0 && (n.name == c.camera || s.cameras[static_cast<std::size_t>(n.camera)].name == c.camera));
    if (!ok) throw SceneError(origin + ": scene config $.camera: no camera node or camera named \"" + c.camera + "\"");
  }
  if (!c.link_loss.text_node.empty() && s.find_node(c.link_loss.text_node) < 0) {
    throw SceneError(origin + ": scene config $.link_loss.text_node: no node named \"" + c.link_loss.text_node + "\"");
  }
  for (std::size_t g = 0; g < c.groups.size(); ++g) {
    for (const auto& m : c.groups[g].members) {
      if (s.find_node(m) < 0) {
        throw SceneError(origin + ": scene config $.groups[" + std::to_string(g) + "].members: no node named \"" + m + "\"");
      }
    }
  }
}

ConvertResult convert_gltf(const std::string& path, const SceneConfig& config, const ConvertOptions& options) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  const bool binary = path.size() >= 4 && (path.compare(path.size() - 4, 4, ".glb") == 0 || path.compare(path.size() - 4, 4, ".GLB") == 0);
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw SceneError(path + ": cannot load glTF: " + (err.empty() ? "unknown tinygltf error" : err));
  }
  Converter c(model, path, config, options);
  return c.run();
}

std::string program_report(const Scene& s) {
  std::ostringstream os;
  std::size_t total_instr = 0;
  os << "scene " << s.source_name << ": " << s.programs.size() << " program(s), " << s.draws.size() << " draw(s)\n";
  for (std::size_t i = 0; i < s.programs.size(); ++i) {
    const auto& e = s.programs[i];
    const auto& p = e.program;
    std::size_t draws = 0;
    for (const auto& d : s.draws) draws += d.program == static_cast<int>(i);
    os << "program " << i << ": " << shadergen::program_key(p.features) << "\n";
    os << "  shading " << shadergen::to_string(p.features.shading) << ", alpha " << shadergen::to_string(p.features.alpha)
       << ", blend " << (p.blend ? "on" : "off") << ", cull " << (p.cull_back_faces ? "back" : "none") << ", draws " << draws << "\n";
    os << "  attributes " << p.attributes.size() << ", uniforms " << p.uniforms.size() << ", samplers " << p.samplers.size()
       << ", source " << p.vertex_source.size() + p.fragment_source.size() << " bytes\n";
    if (p.optimized) {
      const auto& r = e.optimize_report;
      total_instr += r.spirv_instructions_after;
      os << "  optimized: SPIR-V instructions " << r.spirv_instructions_before << " -> " << r.spirv_instructions_after
         << ", uniforms " << r.uniforms_before << " -> " << r.uniforms_after << ", varyings " << r.varyings_before << " -> "
         << r.varyings_after << ", folded " << r.folded.size() << "\n";
    } else {
      total_instr += e.optimize_report.spirv_instructions_after;
      os << "  not optimized: SPIR-V instructions " << e.optimize_report.spirv_instructions_after << "\n";
    }
  }
  if (total_instr) os << "total SPIR-V instructions (vertex + fragment, all programs): " << total_instr << "\n";
  return os.str();
}

}  // namespace meter::engine
