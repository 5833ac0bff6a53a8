// Checks the committed scenes against the contracts other rooms rely on, reading the exported
// .glb (TinyGLTF) and the binding files (nlohmann::json) independently of the engine's own parser:
// - every binding names a catalog signal and a node / material / animation that exists;
// - value-driven animation: binding value v maps to a keyed pose whose needle angle is the dial's
//   angle for v (frame k = value k), sampled from the exported quaternions;
// - minimal-gauge: the pixel geometry written in its README (pivot (320, 240), 200 px per unit,
//   angle -120 + 240 v / 260 clockwise from up) follows from the exported camera and needle;
// - cluster: >= 150 mesh objects, >= 14 telltales in their ISO 2575 colour class, the glTF
//   the features a production cluster has; feature scenes: a 640x480 reference and their feature's data.
#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "meter/protocol/catalog.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kScenes = fs::path(METER_SOURCE_DIR) / "scenes";
const std::vector<std::string> kFeatures = {"ambient",  "diffuse",    "specular", "shininess",
                                            "emission", "bump",       "reflection", "envmap2d",
                                            "skinning", "morphing",   "spot",     "omni",
                                            "shadow"};

struct Scene {
  std::string name;
  fs::path glb;
  fs::path config;
};

std::vector<Scene> all_scenes() {
  std::vector<Scene> out{
      {"minimal-gauge", kScenes / "minimal-gauge/minimal-gauge.glb",
       kScenes / "minimal-gauge/minimal-gauge.scene.json"},
      {"cluster", kScenes / "cluster/cluster.glb", kScenes / "cluster/cluster.scene.json"}};
  for (const auto& f : kFeatures) {
    out.push_back({f, kScenes / "features" / f / (f + ".glb"), kScenes / "features" / f / "scene.json"});
  }
  return out;
}

tinygltf::Model load_glb(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  if (!loader.LoadBinaryFromFile(&model, &err, &warn, path.string())) {
    ADD_FAILURE() << path << ": TinyGLTF cannot load it: " << err;
  }
  return model;
}

json load_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) {
    ADD_FAILURE() << path << ": cannot open";
    return json::object();
  }
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    ADD_FAILURE() << path << ": not valid JSON: " << e.what();
    return json::object();
  }
}

int find_node(const tinygltf::Model& m, const std::string& name) {
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    if (m.nodes[i].name == name) return static_cast<int>(i);
  }
  return -1;
}
int find_material(const tinygltf::Model& m, const std::string& name) {
  for (std::size_t i = 0; i < m.materials.size(); ++i) {
    if (m.materials[i].name == name) return static_cast<int>(i);
  }
  return -1;
}
const tinygltf::Animation* find_animation(const tinygltf::Model& m, const std::string& name) {
  for (const auto& a : m.animations) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

// Reads a float accessor (SCALAR / VEC4) honouring byteStride.
std::vector<float> read_floats(const tinygltf::Model& m, int accessor_index) {
  const auto& acc = m.accessors.at(static_cast<std::size_t>(accessor_index));
  EXPECT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const auto& view = m.bufferViews.at(static_cast<std::size_t>(acc.bufferView));
  const auto& buf = m.buffers.at(static_cast<std::size_t>(view.buffer));
  const int comps = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
  const std::size_t stride = view.byteStride ? view.byteStride : sizeof(float) * static_cast<std::size_t>(comps);
  std::vector<float> out;
  out.reserve(acc.count * static_cast<std::size_t>(comps));
  for (std::size_t i = 0; i < acc.count; ++i) {
    const std::size_t at = view.byteOffset + acc.byteOffset + i * stride;
    for (int c = 0; c < comps; ++c) {
      float f;
      std::memcpy(&f, buf.data.data() + at + sizeof(float) * static_cast<std::size_t>(c), sizeof f);
      out.push_back(f);
    }
  }
  return out;
}

// One rotation channel; at(t) samples it as a LINEAR glTF sampler does (slerp, clamped ends).
struct RotationTrack {
  int node = -1;
  std::vector<float> times;
  std::vector<glm::quat> keys;
  glm::quat at(double t) const {
    if (t <= times.front()) return keys.front();
    if (t >= times.back()) return keys.back();
    // t can round (as float) onto the last key while being below it as a double: clamp the
    // interval index so it always names a valid [i - 1, i] pair.
    auto it = std::upper_bound(times.begin(), times.end(), static_cast<float>(t));
    const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - times.begin()), 1, times.size() - 1);
    const double a = (t - times[i - 1]) / (times[i] - times[i - 1]);
    return glm::slerp(keys[i - 1], keys[i], static_cast<float>(a));
  }
};

RotationTrack rotation_track(const tinygltf::Model& m, const tinygltf::Animation& anim) {
  RotationTrack tr;
  for (const auto& ch : anim.channels) {
    if (ch.target_path != "rotation") continue;
    const auto& s = anim.samplers.at(static_cast<std::size_t>(ch.sampler));
    EXPECT_EQ(s.interpolation, "LINEAR") << anim.name;
    tr.node = ch.target_node;
    tr.times = read_floats(m, s.input);
    auto q = read_floats(m, s.output);
    for (std::size_t i = 0; i + 3 < q.size(); i += 4) tr.keys.emplace_back(q[i + 3], q[i], q[i + 1], q[i + 2]);
  }
  return tr;
}

// A dial lies in the glTF XZ plane facing +Y (Blender's XY facing +Z) and the camera looks down
// -Y with screen-up = -Z. A needle rests pointing screen-up; its screen angle, clockwise from up,
// is atan2(right, up) of the rotated rest direction.
double screen_angle_deg(const glm::quat& q) {
  const glm::vec3 d = q * glm::vec3(0.0f, 0.0f, -1.0f);
  return glm::degrees(std::atan2(static_cast<double>(d.x), static_cast<double>(-d.z)));
}

double angle_diff(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

// ---------------------------------------------------------------- bindings resolve

class SceneTest : public ::testing::TestWithParam<Scene> {};

TEST_P(SceneTest, BindingsResolveAgainstGlbAndCatalog) {
  const Scene& s = GetParam();
  ASSERT_TRUE(fs::exists(s.glb)) << s.glb;
  ASSERT_TRUE(fs::exists(s.config)) << s.config;
  const auto model = load_glb(s.glb);
  const json cfg = load_json(s.config);
  EXPECT_EQ(cfg.value("format", ""), "meter-scene-config/1") << s.config;
  ASSERT_TRUE(cfg.contains("size")) << s.config;
  const int expect_w = s.name == "cluster" ? 1280 : 640;
  EXPECT_EQ(cfg["size"][0].get<int>(), expect_w) << s.config;
  EXPECT_EQ(cfg["size"][1].get<int>(), 480) << s.config;
  const int cam = find_node(model, cfg.value("camera", ""));
  ASSERT_GE(cam, 0) << s.config << ": camera node '" << cfg.value("camera", "") << "' not in " << s.glb;
  EXPECT_GE(model.nodes[static_cast<std::size_t>(cam)].camera, 0) << "camera node has no camera";
  ASSERT_TRUE(cfg.contains("ambient")) << s.config << ": the reference's world light must be stated";

  const auto& bindings = cfg.at("bindings");
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const json& b = bindings[i];
    const std::string where = s.config.string() + ": $.bindings[" + std::to_string(i) + "]";
    const std::string sig = b.value("signal", "");
    const auto* info = meter::protocol::find_signal(sig);
    ASSERT_NE(info, nullptr) << where << ": signal '" << sig << "' is not in the catalog";
    const std::string kind = b.value("kind", "");
    if (kind == "animation") {
      const auto* anim = find_animation(model, b.value("animation", ""));
      ASSERT_NE(anim, nullptr) << where << ": no animation '" << b.value("animation", "") << "'";
      const auto in = b.at("input").get<std::vector<double>>();
      const auto tm = b.at("time").get<std::vector<double>>();
      ASSERT_EQ(in.size(), 2u);
      ASSERT_EQ(tm.size(), 2u);
      EXPECT_LT(in[0], in[1]) << where;
      EXPECT_GE(in[0], info->min) << where << ": input below the catalog range";
      EXPECT_LE(in[1], info->max) << where << ": input above the catalog range";
      const auto tr = rotation_track(model, *anim);
      ASSERT_FALSE(tr.times.empty()) << where;
      EXPECT_NEAR(tm[0], tr.times.front(), 1e-4) << where << ": time range must span the keys";
      EXPECT_NEAR(tm[1], tr.times.back(), 1e-4) << where << ": time range must span the keys";
      EXPECT_TRUE(b.contains("failsafe") && b["failsafe"].contains("value")) << where;
    } else if (kind == "visibility") {
      EXPECT_GE(find_node(model, b.value("node", "")), 0) << where << ": no node '" << b.value("node", "") << "'";
      EXPECT_TRUE(b.contains("failsafe") && b["failsafe"].contains("visible")) << where;
    } else if (kind == "emissive") {
      EXPECT_GE(find_material(model, b.value("material", "")), 0)
          << where << ": no material '" << b.value("material", "") << "'";
    } else if (kind == "text") {
      const int n = find_node(model, b.value("node", ""));
      ASSERT_GE(n, 0) << where << ": no node '" << b.value("node", "") << "'";
      EXPECT_LT(model.nodes[static_cast<std::size_t>(n)].mesh, 0) << where << ": a text anchor is an empty";
      EXPECT_TRUE(b.contains("failsafe") && b["failsafe"].contains("text")) << where;
    } else {
      ADD_FAILURE() << where << ": unexpected kind '" << kind << "'";
    }
  }
  if (cfg.contains("link_loss")) {
    EXPECT_GE(find_node(model, cfg["link_loss"].value("text_node", "")), 0) << s.config;
  }
  for (const auto& g : cfg.value("groups", json::array())) {
    for (const auto& member : g.at("members")) {
      EXPECT_GE(find_node(model, member.get<std::string>()), 0)
          << s.config << ": group " << g.value("name", "") << " member " << member;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(All, SceneTest, ::testing::ValuesIn(all_scenes()),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

// ---------------------------------------------------------------- value-driven animation

struct DialSpec {
  std::string animation;
  double start_deg, sweep_deg;  // screen angle at input[0], sweep to input[1]
};

// For every animation binding: value v -> time by the binding's linear map -> sampled pose ->
// screen angle, compared with the dial's printed scale. Checked at every key and half way between.
void check_dials(const fs::path& glb, const fs::path& config, const std::vector<DialSpec>& dials) {
  const auto model = load_glb(glb);
  const json cfg = load_json(config);
  for (const auto& d : dials) {
    const json* binding = nullptr;
    for (const auto& b : cfg.at("bindings")) {
      if (b.value("kind", "") == "animation" && b.value("animation", "") == d.animation) binding = &b;
    }
    ASSERT_NE(binding, nullptr) << config << ": no binding drives " << d.animation;
    const auto in = binding->at("input").get<std::vector<double>>();
    const auto tm = binding->at("time").get<std::vector<double>>();
    const auto* anim = find_animation(model, d.animation);
    ASSERT_NE(anim, nullptr) << d.animation;
    const auto tr = rotation_track(model, *anim);
    ASSERT_GE(tr.keys.size(), 2u);
    const double span = in[1] - in[0];
    int checked = 0;
    for (double v = in[0]; v <= in[1] + 1e-9; v += span / 52.0) {
      const double t = tm[0] + (v - in[0]) / span * (tm[1] - tm[0]);
      const double want = d.start_deg + d.sweep_deg * (v - in[0]) / span;
      const double got = screen_angle_deg(tr.at(t));
      EXPECT_NEAR(angle_diff(got, want), 0.0, 0.05) << d.animation << " at value " << v << " (t " << t << ")";
      ++checked;
    }
    EXPECT_EQ(checked, 53);
  }
}

TEST(SceneAnimation, MinimalGaugeNeedleFollowsFrameEqualsValue) {
  check_dials(kScenes / "minimal-gauge/minimal-gauge.glb", kScenes / "minimal-gauge/minimal-gauge.scene.json",
              {{"SpeedNeedle", -120.0, 240.0}});
}

TEST(SceneAnimation, ClusterNeedlesFollowTheirScales) {
  check_dials(kScenes / "cluster/cluster.glb", kScenes / "cluster/cluster.scene.json",
              {{"SpeedNeedle", -120.0, 240.0},
               {"RpmNeedle", -120.0, 240.0},
               {"FuelNeedle", -50.0, 100.0},
               {"CoolantNeedle", -50.0, 100.0}});
}

TEST(SceneAnimation, SpeedNeedleKeyFrameKIsKKmh) {
  // The paper's contract literally: the key at frame k (24 fps) shows k km/h.
  const auto model = load_glb(kScenes / "cluster/cluster.glb");
  const auto* anim = find_animation(model, "SpeedNeedle");
  ASSERT_NE(anim, nullptr);
  const auto tr = rotation_track(model, *anim);
  ASSERT_EQ(tr.times.size(), 261u);
  for (std::size_t k = 0; k <= 260; k += 13) {
    EXPECT_NEAR(tr.times[k], static_cast<double>(k) / 24.0, 1e-5);
    EXPECT_NEAR(angle_diff(screen_angle_deg(tr.keys[k]), -120.0 + 240.0 * static_cast<double>(k) / 260.0), 0.0, 0.02)
        << "frame " << k;
  }
}

// ---------------------------------------------------------------- minimal-gauge README geometry

glm::mat4 node_matrix(const tinygltf::Node& n) {
  glm::mat4 m(1.0f);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::vec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4)
    m *= glm::mat4_cast(glm::quat(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                                  static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2])));
  return m;
}

TEST(MinimalGauge, ReadmePixelGeometryMatchesExport) {
  const auto model = load_glb(kScenes / "minimal-gauge/minimal-gauge.glb");
  const int cam_node = find_node(model, "Camera");
  ASSERT_GE(cam_node, 0);
  const auto& cn = model.nodes[static_cast<std::size_t>(cam_node)];
  const auto& cam = model.cameras.at(static_cast<std::size_t>(cn.camera));
  ASSERT_EQ(cam.type, "orthographic");
  // 640 px across 2 * xmag units, 480 px across 2 * ymag: 200 px per unit both ways.
  EXPECT_NEAR(640.0 / (2.0 * cam.orthographic.xmag), 200.0, 1e-3);
  EXPECT_NEAR(480.0 / (2.0 * cam.orthographic.ymag), 200.0, 1e-3);
  const glm::mat4 view = glm::inverse(node_matrix(cn));
  // Camera looks along -Y (straight at the dial), screen-up is -Z, screen-right +X.
  const glm::vec3 fwd = glm::vec3(node_matrix(cn) * glm::vec4(0, 0, -1, 0));
  EXPECT_NEAR(fwd.y, -1.0f, 1e-5f);
  const int needle = find_node(model, "Needle");
  ASSERT_GE(needle, 0);
  const auto& nn = model.nodes[static_cast<std::size_t>(needle)];
  ASSERT_EQ(nn.translation.size(), 3u);
  const glm::vec4 pivot_world(static_cast<float>(nn.translation[0]), static_cast<float>(nn.translation[1]),
                              static_cast<float>(nn.translation[2]), 1.0f);
  const glm::vec4 pv = view * pivot_world;
  const double px = 320.0 + pv.x * 640.0 / (2.0 * cam.orthographic.xmag);
  const double py = 240.0 - pv.y * 480.0 / (2.0 * cam.orthographic.ymag);
  EXPECT_NEAR(px, 320.0, 1e-3);
  EXPECT_NEAR(py, 240.0, 1e-3);
}

// ---------------------------------------------------------------- cluster content

int mesh_node_count(const tinygltf::Model& m) {
  return static_cast<int>(std::count_if(m.nodes.begin(), m.nodes.end(), [](const auto& n) { return n.mesh >= 0; }));
}

enum class Iso { Red, Amber, Green, Blue, Other };
Iso classify(const std::vector<double>& c) {
  const double r = c.at(0), g = c.at(1), b = c.at(2);
  if (b > 0.6 && r < 0.3 && g < 0.5) return Iso::Blue;
  if (g > 0.6 && r < 0.3 && b < 0.4) return Iso::Green;
  if (r > 0.8 && g > 0.25 && g < 0.7 && b < 0.2) return Iso::Amber;
  if (r > 0.8 && g < 0.15 && b < 0.15) return Iso::Red;
  return Iso::Other;
}

TEST(Cluster, TelltalesHaveTheirIsoColourClass) {
  // UN R121 Table 1 / ISO 2575 colours for the cluster's telltales.
  const std::map<std::string, Iso> expected = {
      {"TurnLeft", Iso::Green},     {"TurnRight", Iso::Green},   {"HighBeam", Iso::Blue},
      {"LowBeam", Iso::Green},      {"FrontFog", Iso::Green},    {"ParkingBrake", Iso::Red},
      {"BrakeFault", Iso::Red},     {"ABS", Iso::Amber},         {"Airbag", Iso::Red},
      {"SeatBelt", Iso::Red},       {"OilPressure", Iso::Red},   {"Battery", Iso::Red},
      {"CheckEngine", Iso::Amber},  {"CoolantTemp", Iso::Red},   {"ESC", Iso::Amber},
      {"TPMS", Iso::Amber}};
  const auto model = load_glb(kScenes / "cluster/cluster.glb");
  const json cfg = load_json(kScenes / "cluster/cluster.scene.json");
  std::set<std::string> visible_bound;
  std::map<std::string, std::vector<double>> emissive_on;
  for (const auto& b : cfg.at("bindings")) {
    const std::string sig = b.value("signal", "");
    if (sig.rfind("Cluster.Telltale.", 0) != 0) continue;
    const std::string lamp = sig.substr(std::strlen("Cluster.Telltale."));
    if (b.value("kind", "") == "visibility") visible_bound.insert(lamp);
    if (b.value("kind", "") == "emissive") emissive_on[lamp] = b.at("on").get<std::vector<double>>();
  }
  EXPECT_GE(visible_bound.size(), 14u);
  for (const auto& [lamp, iso] : expected) {
    EXPECT_TRUE(visible_bound.count(lamp)) << lamp << " has no visibility binding";
    ASSERT_TRUE(emissive_on.count(lamp)) << lamp << " has no emissive binding";
    EXPECT_EQ(classify(emissive_on[lamp]), iso) << lamp;
    // The exported material shows the same colour when lit (what a bulb check renders).
    const int mat = find_material(model, "TT_" + lamp + "_On");
    ASSERT_GE(mat, 0) << lamp;
    EXPECT_EQ(classify(model.materials[static_cast<std::size_t>(mat)].emissiveFactor), iso) << lamp;
    const int node = find_node(model, "TT_" + lamp);
    ASSERT_GE(node, 0) << lamp;
    EXPECT_GE(model.nodes[static_cast<std::size_t>(node)].mesh, 0) << lamp;
  }
}

TEST(Cluster, ProductionFeatures) {
  const auto model = load_glb(kScenes / "cluster/cluster.glb");
  EXPECT_GE(mesh_node_count(model), 150) << "the paper's product scene has 154 objects";
  // KHR_lights_punctual with every light type.
  std::set<std::string> types;
  for (const auto& l : model.lights) types.insert(l.type);
  EXPECT_EQ(types, (std::set<std::string>{"directional", "point", "spot"}));
  // A normal-mapped dial face whose primitives carry UVs and tangents.
  const int face_mat = find_material(model, "DialFace");
  ASSERT_GE(face_mat, 0);
  ASSERT_GE(model.materials[static_cast<std::size_t>(face_mat)].normalTexture.index, 0);
  int faces = 0;
  for (const auto& mesh : model.meshes) {
    for (const auto& p : mesh.primitives) {
      if (p.material != face_mat) continue;
      ++faces;
      EXPECT_TRUE(p.attributes.count("TEXCOORD_0")) << mesh.name;
      EXPECT_TRUE(p.attributes.count("TANGENT")) << mesh.name;
    }
  }
  EXPECT_EQ(faces, 2) << "speedometer and tachometer faces";
  // Chrome: fully metallic, low roughness; needles emissive.
  const int chrome = find_material(model, "Chrome");
  ASSERT_GE(chrome, 0);
  EXPECT_DOUBLE_EQ(model.materials[static_cast<std::size_t>(chrome)].pbrMetallicRoughness.metallicFactor, 1.0);
  EXPECT_LE(model.materials[static_cast<std::size_t>(chrome)].pbrMetallicRoughness.roughnessFactor, 0.2);
  const int needle = find_material(model, "Needle");
  ASSERT_GE(needle, 0);
  EXPECT_GT(model.materials[static_cast<std::size_t>(needle)].emissiveFactor.at(0), 0.5);
  for (const char* text : {"Text_Gear", "Text_Speed", "Text_Odometer", "Text_Trip", "Text_OutsideTemp", "Text_Status"}) {
    const int n = find_node(model, text);
    ASSERT_GE(n, 0) << text;
    EXPECT_LT(model.nodes[static_cast<std::size_t>(n)].mesh, 0) << text << " must be an empty (text anchor)";
  }
}

// ---------------------------------------------------------------- feature scenes

// Width and height from a PNG's IHDR (bytes 16..23), the only part of the file this test needs.
std::pair<std::uint32_t, std::uint32_t> png_size(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (in.gcount() != 24 || std::memcmp(h, "\x89PNG\r\n\x1a\n", 8) != 0 || std::memcmp(h + 12, "IHDR", 4) != 0) {
    ADD_FAILURE() << path << ": not a PNG";
    return {0, 0};
  }
  auto be = [&](int o) {
    return (std::uint32_t{h[o]} << 24) | (std::uint32_t{h[o + 1]} << 16) | (std::uint32_t{h[o + 2]} << 8) | h[o + 3];
  };
  return {be(16), be(20)};
}

class FeatureTest : public ::testing::TestWithParam<std::string> {};

TEST_P(FeatureTest, ReferenceAndFeatureData) {
  const std::string f = GetParam();
  const fs::path dir = kScenes / "features" / f;
  const auto [w, h] = png_size(dir / "reference.png");
  EXPECT_EQ(w, 640u);
  EXPECT_EQ(h, 480u);
  const auto model = load_glb(dir / (f + ".glb"));
  const json cfg = load_json(dir / "scene.json");
  const int pot = find_node(model, "Teapot");
  ASSERT_GE(pot, 0) << "one teapot per scene";
  const auto& mesh = model.meshes.at(static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(pot)].mesh));
  const auto& mat = model.materials.at(static_cast<std::size_t>(mesh.primitives.at(0).material));
  const auto ambient = cfg.at("ambient").get<std::vector<double>>();
  const bool world_lit = f == "ambient" || f == "reflection" || f == "envmap2d";
  EXPECT_EQ(ambient != std::vector<double>({0.0, 0.0, 0.0}), world_lit) << "ambient only where the world lights the reference";
  if (f == "reflection" || f == "envmap2d") {
    const auto& extras = model.scenes.at(0).extras;
    ASSERT_TRUE(extras.Has("meter_environment")) << "environment map named in the scene extras";
    EXPECT_TRUE(fs::exists(dir / extras.Get("meter_environment").Get<std::string>()));
    EXPECT_TRUE(model.lights.empty()) << "lit by the environment only";
  } else {
    EXPECT_FALSE(model.lights.empty());
  }
  if (f == "emission") {
    EXPECT_GT(mat.emissiveFactor.at(1), 0.5);
  }
  if (f == "bump") {
    EXPECT_GE(mat.normalTexture.index, 0);
    EXPECT_TRUE(mesh.primitives.at(0).attributes.count("TANGENT"));
  }
  if (f == "reflection") {
    EXPECT_DOUBLE_EQ(mat.pbrMetallicRoughness.metallicFactor, 1.0);
  }
  if (f == "shininess" || f == "specular") {
    // Same material but for roughness: the pair isolates the highlight's size.
    const auto other = load_glb(kScenes / "features" / (f == "shininess" ? "specular" : "shininess") /
                                (f == "shininess" ? "specular.glb" : "shininess.glb"));
    const double mine = mat.pbrMetallicRoughness.roughnessFactor;
    const double theirs = other.materials.at(0).pbrMetallicRoughness.roughnessFactor;
    EXPECT_EQ(f == "shininess", mine < theirs);
  }
  if (f == "skinning") {
    ASSERT_EQ(model.skins.size(), 1u);
    EXPECT_EQ(model.nodes[static_cast<std::size_t>(pot)].skin, 0);
    ASSERT_NE(find_animation(model, "Bend"), nullptr);
  }
  if (f == "morphing") {
    EXPECT_EQ(mesh.primitives.at(0).targets.size(), 1u);
    const auto* a = find_animation(model, "Squash");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->channels.at(0).target_path, "weights");
  }
  if (f == "skinning" || f == "morphing") {
    EXPECT_NEAR(cfg.at("time").get<double>(), 0.5, 1e-6) << "reference rendered half way";
  }
  if (f == "spot") {
    ASSERT_EQ(model.lights.size(), 1u);
    EXPECT_EQ(model.lights[0].type, "spot");
    EXPECT_LT(model.lights[0].spot.innerConeAngle, model.lights[0].spot.outerConeAngle);
  }
  if (f == "omni") {
    ASSERT_EQ(model.lights.size(), 1u);
    EXPECT_EQ(model.lights[0].type, "point");
  }
  // Lights cast shadows only where that is the feature: the exporter's extras.meter_cast_shadow
  // (Blender's use_shadow); absent means no shadow.
  std::set<std::string> casting;
  for (const auto& l : model.lights)
    if (l.extras.IsObject() && l.extras.Has("meter_cast_shadow")) {
      const auto& v = l.extras.Get("meter_cast_shadow");
      if ((v.IsBool() && v.Get<bool>()) || (v.IsInt() && v.Get<int>() != 0)) casting.insert(l.type);
    }
  if (f == "shadow") {
    EXPECT_EQ(casting, (std::set<std::string>{"directional", "spot"})) << "a sun and a spot, both casting";
    ASSERT_GE(find_node(model, "Floor"), 0) << "the shadows need a floor to fall on";
  } else {
    EXPECT_TRUE(casting.empty()) << f << ": a light casts shadows";
  }
}

INSTANTIATE_TEST_SUITE_P(All, FeatureTest, ::testing::ValuesIn(kFeatures));

}  // namespace
