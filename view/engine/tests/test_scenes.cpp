#include "test_scenes.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <tiny_gltf.h>

#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"

namespace meter::engine::test {
namespace {

struct Builder {
  tinygltf::Model m;
  std::vector<unsigned char> data;

  int accessor(const std::vector<float>& v, int type, int comps, bool minmax = false) {
    const std::size_t offset = data.size();
    data.resize(offset + v.size() * 4);
    std::memcpy(data.data() + offset, v.data(), v.size() * 4);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = offset;
    bv.byteLength = v.size() * 4;
    m.bufferViews.push_back(bv);
    tinygltf::Accessor a;
    a.bufferView = static_cast<int>(m.bufferViews.size() - 1);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = v.size() / static_cast<std::size_t>(comps);
    if (minmax) {
      a.minValues.assign(static_cast<std::size_t>(comps), 1e30);
      a.maxValues.assign(static_cast<std::size_t>(comps), -1e30);
      for (std::size_t i = 0; i < v.size(); ++i) {
        auto c = i % static_cast<std::size_t>(comps);
        a.minValues[c] = std::min<double>(a.minValues[c], v[i]);
        a.maxValues[c] = std::max<double>(a.maxValues[c], v[i]);
      }
    }
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size() - 1);
  }
  int indices(const std::vector<std::uint16_t>& v) {
    const std::size_t offset = data.size();
    data.resize(offset + v.size() * 2 + (v.size() % 2) * 2);  // keep 4-byte alignment
    std::memcpy(data.data() + offset, v.data(), v.size() * 2);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = offset;
    bv.byteLength = v.size() * 2;
    m.bufferViews.push_back(bv);
    tinygltf::Accessor a;
    a.bufferView = static_cast<int>(m.bufferViews.size() - 1);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = v.size();
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size() - 1);
  }
  int material(const std::string& name, std::vector<double> color, bool unlit, std::vector<double> emissive = {0, 0, 0}) {
    tinygltf::Material mat;
    mat.name = name;
    mat.pbrMetallicRoughness.baseColorFactor = std::move(color);
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.6;
    mat.emissiveFactor = std::move(emissive);
    if (unlit) {
      mat.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
      if (std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), "KHR_materials_unlit") == m.extensionsUsed.end()) {
        m.extensionsUsed.push_back("KHR_materials_unlit");
      }
    }
    m.materials.push_back(mat);
    return static_cast<int>(m.materials.size() - 1);
  }
  // Axis-aligned quad in the z plane, facing +Z.
  int quad_mesh(const std::string& name, float x0, float y0, float x1, float y1, float z, int mat, bool normals,
                const std::vector<float>* morph = nullptr) {
    std::vector<float> pos{x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z};
    tinygltf::Primitive p;
    p.attributes["POSITION"] = accessor(pos, TINYGLTF_TYPE_VEC3, 3, true);
    if (normals) p.attributes["NORMAL"] = accessor({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, TINYGLTF_TYPE_VEC3, 3);
    p.indices = indices({0, 1, 2, 0, 2, 3});
    p.material = mat;
    p.mode = TINYGLTF_MODE_TRIANGLES;
    // Two targets (grow, and a sideways shift the bindings never drive): shadergen 1-target
    // programs currently fail to compile (u_morph_weights declared without array).
    if (morph) {
      p.targets.push_back({{"POSITION", accessor(*morph, TINYGLTF_TYPE_VEC3, 3, true)}});
      std::vector<float> shift(morph->size(), 0.0f);
      for (std::size_t i = 0; i < shift.size(); i += 3) shift[i] = 0.1f;
      p.targets.push_back({{"POSITION", accessor(shift, TINYGLTF_TYPE_VEC3, 3, true)}});
    }
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(p);
    if (morph) mesh.weights = {0.0, 0.0};
    m.meshes.push_back(mesh);
    return static_cast<int>(m.meshes.size() - 1);
  }
  int node(const std::string& name, std::vector<double> t = {}, int mesh = -1) {
    tinygltf::Node n;
    n.name = name;
    n.translation = std::move(t);
    n.mesh = mesh;
    m.nodes.push_back(n);
    return static_cast<int>(m.nodes.size() - 1);
  }
};

}  // namespace

const Scene& cluster_scene() {
  static const Scene s = [] {
    const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/cluster/";
    return convert::convert_gltf(dir + "cluster.glb", meter::config::load_scene_config(dir + "cluster.scene.json"), convert::ConvertOptions{}).scene;
  }();
  return s;
}

std::string scratch_dir(const std::string& name) {
  namespace fs = std::filesystem;
  // One directory per test process: ctest -j runs a suite's tests (e.g. the egl and osmesa
  // instances of one render test) as concurrent processes, which must not write and delete the
  // same files. Directories of processes that have ended are removed on the first call.
  const fs::path root = fs::path(METER_BINARY_DIR) / "test-scratch" / "engine";
  static const fs::path mine = [&] {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root, ec)) {
      const std::string n = e.path().filename().string();
      if (n.empty() || n.find_first_not_of("0123456789") != std::string::npos) continue;
      const long pid = std::strtol(n.c_str(), nullptr, 10);
      if (pid > 0 && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) fs::remove_all(e.path(), ec);
    }
    return root / std::to_string(getpid());
  }();
  fs::path p = mine / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

std::string write_dial_scene(const std::string& dir) {
  Builder b;
  const int dial_mat = b.material("Dial", {0.02, 0.02, 0.03, 1.0}, true);
  const int needle_mat = b.material("NeedleMat", {1.0, 0.08, 0.02, 1.0}, true);
  const int tt_mat = b.material("TT_ABS_On", {0.05, 0.05, 0.05, 1.0}, false);
  const int bar_mat = b.material("FuelBarMat", {0.1, 0.8, 0.2, 1.0}, true);
  const int dial = b.node("Dial", {}, b.quad_mesh("DialMesh", -1.0f, -1.0f, 1.0f, 1.0f, 0.0f, dial_mat, false));
  const int needle_mesh = b.quad_mesh("NeedleMesh", -0.03f, -0.1f, 0.03f, 0.85f, 0.02f, needle_mat, false);
  const int needle = b.node("Needle");
  const int needle_geo = b.node("NeedleGeo", {}, needle_mesh);
  b.m.nodes[static_cast<std::size_t>(needle)].children = {needle_geo};
  const int tt = b.node("TT_ABS", {0.75, -0.75, 0.0}, b.quad_mesh("TTMesh", -0.12f, -0.12f, 0.12f, 0.12f, 0.01f, tt_mat, true));
  const std::vector<float> grow{0, 0, 0, 0, 0, 0, 0, 0.6f, 0, 0, 0.6f, 0};
  const int bar = b.node("FuelBar", {}, b.quad_mesh("FuelBarMesh", -0.95f, -0.95f, -0.85f, -0.9f, 0.01f, bar_mat, false, &grow));
  const int text_speed = b.node("Text_Speed", {0.0, -0.45, 0.03});
  const int text_status = b.node("Text_Status", {0.0, 0.45, 0.03});
  // Directional light shining straight at the dial (down -Z, the node's default direction).
  tinygltf::Light sun;
  sun.name = "Sun";
  sun.type = "directional";
  sun.color = {1.0, 1.0, 1.0};
  sun.intensity = 3.0;
  b.m.lights.push_back(sun);
  const int light = b.node("Sun", {0.0, 0.0, 2.0});
  tinygltf::Value::Object lo;
  lo["light"] = tinygltf::Value(0);
  b.m.nodes[static_cast<std::size_t>(light)].extensions["KHR_lights_punctual"] = tinygltf::Value(lo);
  b.m.extensionsUsed.push_back("KHR_lights_punctual");
  tinygltf::Camera cam;
  cam.name = "CameraData";
  cam.type = "perspective";
  cam.perspective.yfov = 0.8;
  cam.perspective.znear = 0.1;
  cam.perspective.zfar = 100.0;
  cam.perspective.aspectRatio = 2.0;
  b.m.cameras.push_back(cam);
  const int camera = b.node("Camera", {0.0, 0.0, 3.0});
  b.m.nodes[static_cast<std::size_t>(camera)].camera = 0;
  // Value-driven needle: key k at time (26 k)/24 s, angle 130 - 26 k degrees.
  std::vector<float> times, rot;
  for (int k = 0; k <= 10; ++k) {
    const double v = 26.0 * k;
    times.push_back(static_cast<float>(v / 24.0));
    const double half = (130.0 - v) * M_PI / 360.0;
    rot.insert(rot.end(), {0.0f, 0.0f, static_cast<float>(std::sin(half)), static_cast<float>(std::cos(half))});
  }
  tinygltf::Animation anim;
  anim.name = "SpeedNeedle";
  tinygltf::AnimationSampler sampler;
  sampler.input = b.accessor(times, TINYGLTF_TYPE_SCALAR, 1, true);
  sampler.output = b.accessor(rot, TINYGLTF_TYPE_VEC4, 4);
  sampler.interpolation = "LINEAR";
  anim.samplers.push_back(sampler);
  tinygltf::AnimationChannel ch;
  ch.sampler = 0;
  ch.target_node = needle;
  ch.target_path = "rotation";
  anim.channels.push_back(ch);
  b.m.animations.push_back(anim);

  tinygltf::Buffer buf;
  buf.data = b.data;
  b.m.buffers.push_back(buf);
  tinygltf::Scene scene;
  scene.nodes = {dial, needle, tt, bar, text_speed, text_status, light, camera};
  b.m.scenes.push_back(scene);
  b.m.defaultScene = 0;
  b.m.asset.version = "2.0";
  b.m.asset.generator = "meter engine tests";
  const std::string path = dir + "/dial.gltf";
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&b.m, path, true, true, true, false)) throw std::runtime_error("cannot write " + path);
  return path;
}

std::string dial_config_json() {
  return R"({
  "format": "meter-scene-config/1",
  "size": [320, 160],
  "camera": "Camera",
  "clear_color": [0, 0, 0, 1],
  "ambient": [0.05, 0.05, 0.05],
  "bindings": [
    {"signal": "Vehicle.Speed", "kind": "animation", "animation": "SpeedNeedle",
     "input": [0, 260], "time": [0.0, 10.8333333], "smoothing_ms": 80, "failsafe": {"value": 0}},
    {"signal": "Cluster.Telltale.ABS", "kind": "emissive", "material": "TT_ABS_On",
     "off": [0, 0, 0], "on": [1, 0.6, 0], "failsafe": {"value": 1}},
    {"signal": "Vehicle.Powertrain.FuelSystem.RelativeLevel", "kind": "morph", "node": "FuelBar",
     "target": 0, "input": [0, 100], "weight": [0, 1]},
    {"signal": "Vehicle.Speed", "kind": "text", "node": "Text_Speed", "format": "%.0f",
     "size_px": 20, "color": [1, 1, 1, 1], "align": "center", "failsafe": {"text": "---"}}
  ],
  "link_loss": {"text_node": "Text_Status", "text": "NO SIGNAL", "size_px": 16}
})";
}

}  // namespace meter::engine::test
