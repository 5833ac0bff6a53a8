// Geometry at the edges (docs/numerics.md, "Geometry"): non-unit / zero normals (Khronos validator
// file and synthetic), degenerate triangles, NaN/Inf positions, negative / zero / huge / tiny scales.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_inverse.hpp>

#include "gltf_builder.hpp"
#include "meter/engine/evaluation/animation.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
using meter::numerics::GltfBuilder;

namespace {

const char* kConfig = R"({"format": "meter-scene-config/1", "size": [64, 64]})";

ConvertResult convert_scene(GltfBuilder& b, const std::string& name) {
  const auto file = b.write(numerics::scratch(name) / "scene.gltf");
  return convert_gltf(file, meter::config::parse_scene_config(kConfig), ConvertOptions{false});
}

std::vector<Diagnostic> convert_errors(GltfBuilder& b, const std::string& name) {
  try {
    convert_scene(b, name);
  } catch (const ConvertError& e) {
    return e.errors;
  }
  return {};
}

bool mentions(const std::vector<Diagnostic>& ds, const std::string& path, const std::string& text) {
  for (const auto& d : ds)
    if (d.path.find(path) != std::string::npos && d.message.find(text) != std::string::npos) return true;
  return false;
}

// Every normal of every primitive: finite and unit length within `tol`.
void expect_unit_normals(const Scene& s, double tol) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives)
      for (const auto& l : p.layout) {
        if (l.semantic != bridge::AttributeSemantic::Normal) continue;
        for (std::uint32_t v = 0; v < p.vertex_count; ++v) {
          const float* n = &p.vertices[v * static_cast<std::size_t>(p.stride) + static_cast<std::size_t>(l.offset)];
          ASSERT_TRUE(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]));
          EXPECT_NEAR(std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]), 1.0, tol);
        }
      }
}

double angle(const glm::vec3& a, const glm::vec3& b) {
  return std::atan2(glm::length(glm::cross(glm::dvec3(a), glm::dvec3(b))), glm::dot(glm::dvec3(a), glm::dvec3(b)));
}

}  // namespace

// The Khronos validator's non-unit normals/tangents file: rejected, each bad vector named.
TEST(Geometry, KhronosNonUnitNormalsAndTangentsAreRejectedByElement) {
  const std::string f = std::string(METER_SHARED_DIR) + "/data/gltf/gltf-validator-tests/mesh_data/normals_tangents_non_unit_invalid_sign.gltf";
  try {
    convert_gltf(f, meter::config::parse_scene_config(kConfig), ConvertOptions{false});
    FAIL() << "non-unit normals accepted";
  } catch (const ConvertError& e) {
    EXPECT_TRUE(mentions(e.errors, "attributes.NORMAL", "not unit length")) << e.what();
    EXPECT_TRUE(mentions(e.errors, "attributes.TANGENT", "not unit length")) << e.what();
  }
}

// Synthetic: normals 0.5 % off unit length are renormalised (output unit within 1e-6); a
// zero-length normal and an Inf normal are errors naming the element (never normalize(0) = NaN).
TEST(Geometry, SlightlyNonUnitNormalsRepairedZeroAndInfRejected) {
  {
    GltfBuilder b;
    const int mat = b.material("M", {1, 1, 1, 1}, false);
    b.node({{"mesh", b.mesh("Q", {0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1.005f, 0, 0.995f, 0, 0.6f, 0.8f * 1.004f, 0}, {0, 1, 2}, mat)}});
    expect_unit_normals(convert_scene(b, "normals-near-unit").scene, 1e-6);
  }
  for (float bad : {0.0f, std::numeric_limits<float>::infinity()}) {
    GltfBuilder b;
    const int mat = b.material("M", {1, 1, 1, 1}, false);
    b.node({{"mesh", b.mesh("Q", {0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1, bad, 0, 0, 0, 0, 1}, {0, 1, 2}, mat)}});
    const auto errs = convert_errors(b, "normals-bad");
    // Zero: the NORMAL attribute's unit-length check names element 1; Inf: the accessor's
    // finiteness check names element 1 and "Infinity" (it runs before the attribute checks).
    const bool named = bad == 0.0f ? mentions(errs, "attributes.NORMAL", "element 1 is not unit length (|v| = 0")
                                   : mentions(errs, "accessors[", "element 1 (component 0) is Infinity");
    EXPECT_TRUE(named) << "normal x = " << bad << ": " << (errs.empty() ? "accepted" : errs[0].path + ": " + errs[0].message);
  }
}

// NaN / +Inf / -Inf positions: rejected with the accessor element named, never drawn.
TEST(Geometry, NanAndInfPositionsAreRejected) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()}) {
    GltfBuilder b;
    const int mat = b.material("M", {1, 1, 1, 1}, true);
    b.node({{"mesh", b.mesh("Q", {0, 0, 0, 1, bad, 0, 1, 1, 0}, {}, {0, 1, 2}, mat)}});
    const auto errs = convert_errors(b, "pos-bad");
    ASSERT_FALSE(errs.empty()) << "position " << bad << " accepted";
    const std::string word = std::isnan(bad) ? "NaN" : bad > 0 ? "Infinity" : "-Infinity";
    bool named = false;
    for (const auto& d : errs) named = named || d.message.find(word) != std::string::npos;
    EXPECT_TRUE(named) << word;
  }
}

// Degenerate triangles: index-degenerate ones are dropped (and reported); zero-area ones with
// distinct indices (collinear points) under lit shading without NORMAL get a finite unit flat
// normal, not normalize(0).
TEST(Geometry, DegenerateTrianglesDroppedOrGivenFiniteNormals) {
  GltfBuilder b;
  const int lit = b.material("Lit", {1, 1, 1, 1}, false);
  // tri 0 fine, tri 1 index-degenerate, tri 2 collinear (zero area), tri 3 all at one point.
  b.node({{"mesh", b.mesh("D", {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 5, 5, 5, 5, 5, 5, 5, 5, 5}, {},
                          {0, 1, 2, 0, 0, 1, 0, 3, 4, 5, 6, 7}, lit)}});
  const auto r = convert_scene(b, "degenerate");
  bool reported = false;
  for (const auto& d : r.repairs) reported = reported || d.message.find("1 degenerate triangle") != std::string::npos;
  EXPECT_TRUE(reported);
  const auto& p = r.scene.meshes.at(0).primitives.at(0);
  EXPECT_EQ(p.indices.size(), 9u);  // three triangles left
  expect_unit_normals(r.scene, 1e-6);
}

// Normal matrix: for ordinary, negative (mirroring), huge (1e6) and tiny (1e-6) scales the
// direction equals inverse-transpose within 1e-6 rad; for zero scale and for scale chains whose
// determinant underflows float (1e-6^3 per axis) it stays finite where inverse-transpose is not.
TEST(Geometry, NormalMatrixFiniteAndCorrectForEveryScale) {
  const glm::quat r = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, 2, 3)));
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  for (glm::vec3 s : {glm::vec3(1), glm::vec3(-1, 1, 1), glm::vec3(-2, -3, 0.5f), glm::vec3(1e6f), glm::vec3(1e-6f),
                      glm::vec3(1e6f, 1e-6f, 1.0f)}) {
    const glm::mat4 m = local_matrix(glm::vec3(5, 6, 7), r, s);
    const glm::vec3 want = glm::inverseTranspose(glm::mat3(m)) * n;
    const glm::vec3 got = normal_matrix(m) * n;
    EXPECT_LT(angle(got, want), 1e-6) << s.x << " " << s.y << " " << s.z;
    // Winding: the renderer flips front faces exactly when the determinant is negative.
    EXPECT_EQ(glm::determinant(glm::mat3(m)) < 0, s.x * s.y * s.z < 0);
  }
  // Zero scale on one axis: a flat dial squashed in z keeps its +z normal; all-zero: finite.
  const glm::mat4 flat = local_matrix(glm::vec3(0), glm::quat(1, 0, 0, 0), glm::vec3(1, 1, 0));
  EXPECT_FALSE(std::isfinite(glm::inverseTranspose(glm::mat3(flat))[0][0]));  // what the renderer used to upload
  const glm::vec3 nz = normal_matrix(flat) * glm::vec3(0, 0, 1);
  EXPECT_LT(angle(nz, glm::vec3(0, 0, 1)), 1e-6);
  const glm::mat3 zero = normal_matrix(local_matrix(glm::vec3(1), r, glm::vec3(0)));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_TRUE(std::isfinite(zero[i][j]));
  // A chain of three 1e-6 scales (1e-18 per axis, det 1e-54 underflows float) and of three 1e6
  // scales (1e18, det overflows float): world matrices finite, normal matrix finite and O(1)
  // (largest entry exactly 1, so the shader's normalize() cannot underflow).
  for (float k : {1e-6f, 1e6f}) {
    Scene sc;
    sc.nodes.resize(3);
    for (int i = 0; i < 3; ++i) {
      sc.nodes[i].scale = glm::vec3(k);
      sc.nodes[i].rotation = r;
      if (i > 0) sc.nodes[i].parent = i - 1, sc.nodes[i - 1].children = {i};
    }
    sc.roots = {0};
    std::vector<glm::mat4> w;
    world_matrices(sc, Pose::rest(sc), w);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) ASSERT_TRUE(std::isfinite(w[2][i][j])) << k;
    const glm::mat3 nm = normal_matrix(w[2]);
    float big = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        ASSERT_TRUE(std::isfinite(nm[i][j]));
        big = std::max(big, std::abs(nm[i][j]));
      }
    EXPECT_EQ(big, 1.0f) << k;
    // Direction: a uniform scale does not change normals, so it is R^3 * n.
    EXPECT_LT(angle(nm * n, r * (r * (r * n))), 1e-5) << k;
  }
}
