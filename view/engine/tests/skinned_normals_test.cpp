// Skinned normals recomputed from the deformed surface (meter/engine/evaluation/skinned_normals.hpp)
// on hand-built primitives, no GL: what the vertex shader makes of the written normal,
// mat3(sum w_k J_k) * n, is compared with the deformed surface's normal known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "meter/engine/evaluation/skinned_normals.hpp"

using namespace meter::engine;
using meter::bridge::AttributeSemantic;

namespace {

// Record: position (3), normal (3), joints (4), weights (4), texcoord (2): 16 floats.
constexpr int kStride = 16;

Primitive make_primitive() {
  Primitive p;
  p.stride = kStride;
  p.layout = {{AttributeSemantic::Position, -1, 3, 0},
              {AttributeSemantic::Normal, -1, 3, 3},
              {AttributeSemantic::Joints0, -1, 4, 6},
              {AttributeSemantic::Weights0, -1, 4, 10},
              {AttributeSemantic::TexCoord0, -1, 2, 14}};
  return p;
}

void add_vertex(Primitive& p, glm::vec3 pos, glm::vec3 normal, float weight1, glm::vec2 uv = {0.0f, 0.0f}) {
  const float rec[kStride] = {pos.x, pos.y, pos.z, normal.x, normal.y, normal.z, 0.0f, 1.0f, 0.0f, 0.0f,
                              1.0f - weight1, weight1, 0.0f, 0.0f, uv.x, uv.y};
  p.vertices.insert(p.vertices.end(), rec, rec + kStride);
  ++p.vertex_count;
}

// A flat n x n grid in the xy-plane over [0, 1]^2 facing +z; the weight of joint 1 is x.
Primitive ramp_grid(int n) {
  Primitive p = make_primitive();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) add_vertex(p, {float(i) / n, float(j) / n, 0.0f}, {0.0f, 0.0f, 1.0f}, float(i) / n);
  auto at = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
  return p;
}

// A regular octahedron: its angle-weighted vertex normals are its vertices' directions.
Primitive octahedron() {
  Primitive p = make_primitive();
  const glm::vec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& x : v) add_vertex(p, x, x, 0.0f);
  p.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return p;
}

// What the vertex shader shades with: the blended joint matrix times the written normal.
glm::vec3 shaded_normal(const Primitive& p, const std::vector<float>& out, std::span<const glm::mat4> joints, std::size_t v) {
  const float* rec = p.vertices.data() + v * kStride;
  const glm::mat4 s = rec[10] * joints[std::size_t(rec[6])] + rec[11] * joints[std::size_t(rec[7])];
  const float* n = out.data() + v * kStride + 3;
  return glm::normalize(glm::mat3(s) * glm::vec3(n[0], n[1], n[2]));
}

}  // namespace

// A weight ramp under a joint that only translates: LBS leaves every normal at +z (the blended
// matrix has no rotation), but the surface is now the plane z = h x, whose normal is
// (-h, 0, 1) / |.|, 26.6 degrees away for h = 0.5. The written normals give exactly that.
TEST(SkinnedNormals, AWeightRampTiltsTheNormalAsTheDeformedSurfaceDoes) {
  const Primitive p = ramp_grid(6);
  ASSERT_TRUE(has_skinned_normals(p));
  const SkinnedNormalsLayout layout = skinned_normals_layout(p);
  const float h = 0.5f;
  const std::vector<glm::mat4> joints = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, h})};
  std::vector<float> out = p.vertices;
  EXPECT_EQ(skin_normals(p, layout, joints, out), 0u);
  const glm::vec3 expected = glm::normalize(glm::vec3(-h, 0.0f, 1.0f));
  for (std::size_t v = 0; v < p.vertex_count; ++v) {
    const glm::vec3 n = shaded_normal(p, out, joints, v);
    EXPECT_NEAR(n.x, expected.x, 1e-5f) << "vertex " << v;
    EXPECT_NEAR(n.y, expected.y, 1e-5f) << "vertex " << v;
    EXPECT_NEAR(n.z, expected.z, 1e-5f) << "vertex " << v;
  }
}

// In the rest pose, and under one rigid motion of every joint, the deformed surface is the rest
// surface moved: the shaded normals are the rest normals moved (the octahedron's rest normals are
// its own angle-weighted normals), as LBS gives them.
TEST(SkinnedNormals, RestPoseAndRigidMotionKeepTheRestNormals) {
  const Primitive p = octahedron();
  const SkinnedNormalsLayout layout = skinned_normals_layout(p);
  const glm::mat4 rigid = glm::rotate(glm::translate(glm::mat4(1.0f), {3.0f, -1.0f, 2.0f}), 1.1f, glm::normalize(glm::vec3(1, 2, 3)));
  for (const glm::mat4& m : {glm::mat4(1.0f), rigid}) {
    const std::vector<glm::mat4> joints = {m, m};
    std::vector<float> out = p.vertices;
    EXPECT_EQ(skin_normals(p, layout, joints, out), 0u);
    for (std::size_t v = 0; v < p.vertex_count; ++v) {
      const float* r = p.vertices.data() + v * kStride + 3;
      const glm::vec3 expected = glm::normalize(glm::mat3(m) * glm::vec3(r[0], r[1], r[2]));
      const glm::vec3 n = shaded_normal(p, out, joints, v);
      EXPECT_NEAR(glm::dot(n, expected), 1.0f, 1e-5f) << "vertex " << v;
    }
  }
}

// A texture seam: a copy of a vertex (same position and normal, another texcoord) belongs to the
// same surface point and gets the same normal, from the faces of both sides.
TEST(SkinnedNormals, CopiesAlongASeamShareOneNormal) {
  Primitive p = make_primitive();
  // Two triangles folded along the edge (0,0,0)-(0,1,0); the right one's edge vertices are copies.
  add_vertex(p, {0, 0, 0}, {0, 0, 1}, 0.0f, {0.0f, 0.0f});
  add_vertex(p, {0, 1, 0}, {0, 0, 1}, 0.0f, {0.0f, 1.0f});
  add_vertex(p, {-1, 0, 0}, {0, 0, 1}, 0.0f);
  add_vertex(p, {0, 0, 0}, {0, 0, 1}, 0.0f, {0.5f, 0.0f});
  add_vertex(p, {0, 1, 0}, {0, 0, 1}, 0.0f, {0.5f, 1.0f});
  add_vertex(p, {1, 0, 1}, {0, 0, 1}, 0.0f);
  p.indices = {0, 1, 2, 3, 5, 4};
  const SkinnedNormalsLayout layout = skinned_normals_layout(p);
  EXPECT_EQ(layout.points, 4u);
  const std::vector<glm::mat4> joints = {glm::mat4(1.0f), glm::mat4(1.0f)};
  std::vector<float> out = p.vertices;
  skin_normals(p, layout, joints, out);
  for (auto [a, b] : {std::pair{0, 3}, std::pair{1, 4}})
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(out[std::size_t(a * kStride + 3 + c)], out[std::size_t(b * kStride + 3 + c)]);
  // The shared normal lies between the two faces' normals (+z and (-1, 0, 1)/sqrt 2).
  const glm::vec3 n = shaded_normal(p, out, joints, 0);
  EXPECT_LT(n.x, -0.1f);
  EXPECT_GT(n.z, 0.5f);
}

// Where no deformed normal exists (every weight 0: the blended matrix is zero; a face collapsed to
// a point; a joint index that is NaN), the rest normal stays and is counted, and nothing is NaN.
TEST(SkinnedNormals, DegenerateCasesKeepTheRestNormalAndNeverGiveNaN) {
  Primitive p = ramp_grid(2);
  for (std::size_t v = 0; v < p.vertex_count; ++v) p.vertices[v * kStride + 10] = p.vertices[v * kStride + 11] = 0.0f;
  p.vertices[6] = std::nanf("");
  const SkinnedNormalsLayout layout = skinned_normals_layout(p);
  const std::vector<glm::mat4> joints = {glm::mat4(1.0f), glm::mat4(0.0f)};
  std::vector<float> out = p.vertices;
  EXPECT_EQ(skin_normals(p, layout, joints, out), std::size_t(p.vertex_count));
  for (std::size_t v = 0; v < p.vertex_count; ++v)
    for (std::size_t c = 3; c < 6; ++c) EXPECT_EQ(out[v * kStride + c], p.vertices[v * kStride + c]) << "vertex " << v;

  // Every vertex collapsed to one point by a zero joint: no face has a normal.
  Primitive q = ramp_grid(2);
  for (std::size_t v = 0; v < q.vertex_count; ++v) q.vertices[v * kStride + 10] = 0.0f, q.vertices[v * kStride + 11] = 1.0f;
  std::vector<float> out_q = q.vertices;
  const std::vector<glm::mat4> collapse = {glm::mat4(1.0f), glm::scale(glm::mat4(1.0f), glm::vec3(0.0f))};
  EXPECT_EQ(skin_normals(q, skinned_normals_layout(q), collapse, out_q), std::size_t(q.vertex_count));
  for (float f : out_q) EXPECT_FALSE(std::isnan(f));
  // An index past the vertex count is skipped, as the shader's draw would never reach it.
  q.indices.insert(q.indices.end(), {0, 1, 999});
  std::vector<float> out_r = q.vertices;
  const std::vector<glm::mat4> rest = {glm::mat4(1.0f), glm::mat4(1.0f)};
  EXPECT_EQ(skin_normals(q, skinned_normals_layout(q), rest, out_r), 0u);
}

// Primitives with morph targets keep LBS normals (their deltas come first); without NORMAL or
// WEIGHTS_0 there is nothing to rewrite.
TEST(SkinnedNormals, OnlySkinnedPrimitivesWithNormalsAndNoMorphTargets) {
  Primitive p = ramp_grid(1);
  EXPECT_TRUE(has_skinned_normals(p));
  p.morph_targets = 1;
  EXPECT_FALSE(has_skinned_normals(p));
  Primitive q = ramp_grid(1);
  q.layout.erase(q.layout.begin() + 3);  // no WEIGHTS_0
  EXPECT_FALSE(has_skinned_normals(q));
}

// The joint matrices are the shader's: inverse(model) * world(joint) * inverse_bind, identity for
// a joint node outside the world list.
TEST(SkinnedNormals, JointMatricesAreTheShaders) {
  Skin skin;
  skin.joints = {1, 7};
  skin.inverse_bind = {glm::translate(glm::mat4(1.0f), {0, -1, 0}), glm::mat4(1.0f)};
  const glm::mat4 model = glm::translate(glm::mat4(1.0f), {5, 0, 0});
  const std::vector<glm::mat4> world = {model, glm::translate(glm::mat4(1.0f), {5, 1, 0})};
  const auto j = joint_matrices(skin, world, model);
  ASSERT_EQ(j.size(), 2u);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      EXPECT_NEAR(j[0][c][r], c == r ? 1.0f : 0.0f, 1e-6f);
      EXPECT_EQ(j[1][c][r], c == r ? 1.0f : 0.0f);
    }
}
