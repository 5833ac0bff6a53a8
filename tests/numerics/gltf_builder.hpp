// Minimal glTF 2.0 writer for the numerics tests: float accessors in one embedded (base64) buffer,
// unlit or lit materials, nodes with TRS, an optional perspective camera. Enough to build the odd
// scenes the hard cases need (zero scale, NaN positions, coplanar layers) without Blender.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace meter::numerics {

class GltfBuilder {
 public:
  using json = nlohmann::json;

  int accessor(const std::vector<float>& v, const char* type, int comps) {
    const std::size_t off = data_.size();
    data_.resize(off + v.size() * 4);
    std::memcpy(data_.data() + off, v.data(), v.size() * 4);
    doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", v.size() * 4}});
    json a = {{"bufferView", doc_["bufferViews"].size() - 1}, {"componentType", 5126}, {"type", type},
              {"count", v.size() / static_cast<std::size_t>(comps)}};
    if (std::string(type) == "VEC3") {  // POSITION needs min/max; harmless elsewhere
      std::vector<double> lo(3, 1e300), hi(3, -1e300);
      for (std::size_t i = 0; i < v.size(); ++i) {
        lo[i % 3] = std::min<double>(lo[i % 3], v[i]);
        hi[i % 3] = std::max<double>(hi[i % 3], v[i]);
      }
      bool finite = true;
      for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(lo[c]) && std::isfinite(hi[c]);
      if (finite) a["min"] = lo, a["max"] = hi;  // NaN/Inf test data: leave min/max out
    }
    doc_["accessors"].push_back(a);
    return static_cast<int>(doc_["accessors"].size() - 1);
  }
  int indices(const std::vector<std::uint32_t>& v) {
    const std::size_t off = data_.size();
    data_.resize(off + v.size() * 4);
    std::memcpy(data_.data() + off, v.data(), v.size() * 4);
    doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", v.size() * 4}});
    doc_["accessors"].push_back({{"bufferView", doc_["bufferViews"].size() - 1}, {"componentType", 5125}, {"type", "SCALAR"}, {"count", v.size()}});
    return static_cast<int>(doc_["accessors"].size() - 1);
  }
  int material(const std::string& name, std::vector<double> rgba, bool unlit) {
    json m = {{"name", name}, {"pbrMetallicRoughness", {{"baseColorFactor", rgba}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}}};
    if (unlit) {
      m["extensions"] = {{"KHR_materials_unlit", json::object()}};
      ext_unlit_ = true;
    }
    doc_["materials"].push_back(m);
    return static_cast<int>(doc_["materials"].size() - 1);
  }
  // Mesh from positions (+ optional normals) and triangle indices.
  int mesh(const std::string& name, const std::vector<float>& pos, const std::vector<float>& normals,
           const std::vector<std::uint32_t>& idx, int material) {
    json attrs = {{"POSITION", accessor(pos, "VEC3", 3)}};
    if (!normals.empty()) attrs["NORMAL"] = accessor(normals, "VEC3", 3);
    json prim = {{"attributes", attrs}, {"material", material}};
    if (!idx.empty()) prim["indices"] = indices(idx);
    doc_["meshes"].push_back({{"name", name}, {"primitives", json::array({prim})}});
    return static_cast<int>(doc_["meshes"].size() - 1);
  }
  // Axis-aligned quad in the plane z, facing +Z.
  int quad(const std::string& name, float x0, float y0, float x1, float y1, float z, int material, bool normals = false) {
    std::vector<float> n;
    if (normals) n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    return mesh(name, {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z}, n, {0, 1, 2, 0, 2, 3}, material);
  }
  int node(json n, bool root = true) {
    doc_["nodes"].push_back(std::move(n));
    const int i = static_cast<int>(doc_["nodes"].size() - 1);
    if (root) doc_["scenes"][0]["nodes"].push_back(i);
    return i;
  }
  int camera(double yfov, double znear, double zfar, double aspect) {
    doc_["cameras"].push_back({{"type", "perspective"},
                               {"perspective", {{"yfov", yfov}, {"znear", znear}, {"zfar", zfar}, {"aspectRatio", aspect}}}});
    return static_cast<int>(doc_["cameras"].size() - 1);
  }
  json& doc() { return doc_; }

  std::string write(const std::filesystem::path& file) {
    json d = doc_;
    d["asset"] = {{"version", "2.0"}};
    d["scene"] = 0;
    if (ext_unlit_) d["extensionsUsed"] = {"KHR_materials_unlit"};
    d["buffers"] = json::array({{{"byteLength", data_.size()}, {"uri", "data:application/octet-stream;base64," + base64(data_)}}});
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << d.dump(1);
    return file.string();
  }

 private:
  static std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
      const std::uint32_t v = (in[i] << 16) | (in[i + 1] << 8) | in[i + 2];
      out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
      const std::uint32_t v = in[i] << 16;
      out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
      const std::uint32_t v = (in[i] << 16) | (in[i + 1] << 8);
      out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
  }
  json doc_ = {{"scenes", json::array({{{"nodes", json::array()}}})}};
  std::vector<std::uint8_t> data_;
  bool ext_unlit_ = false;
};

inline std::filesystem::path scratch(const std::string& name) {
  auto d = std::filesystem::path(METER_BINARY_DIR) / "numerics-scratch" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace meter::numerics
