// Flat lists (meter/convert/flat_geometry.hpp): each face's provoking (last) vertex carries the
// face normal, other lists and vertices untouched.
#include <gtest/gtest.h>

#include "meter/convert/flat_geometry.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;

namespace {

glm::vec3 face(const std::vector<glm::vec3>& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return glm::normalize(glm::cross(p[b] - p[a], p[c] - p[a]));
}

// The same triangle (as a set of positions) in the same winding: a rotation of the original.
bool same_triangle(const std::uint32_t* orig, const std::uint32_t* flat, const std::vector<glm::vec3>& pos,
                   const std::vector<glm::vec3>& flat_pos) {
  for (int r = 0; r < 3; ++r) {
    bool all = true;
    for (int k = 0; k < 3; ++k) all = all && pos[orig[(k + r) % 3]] == flat_pos[flat[k]];
    if (all) return true;
  }
  return false;
}

}  // namespace

// A smooth tent (two faces meeting at a ridge, the ridge's normals averaged): the faces get copies
// with their normals; a hard-edged quad (corner normals = the face's) needs none.
TEST(FlatGeometry, ProvokingVertexCarriesTheFaceNormal) {
  const std::vector<glm::vec3> pos{{-1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {-1, 1, 0}, {1, 0, 0}, {1, 1, 0}};
  // Averaged normals everywhere: no corner's normal is its face's (the faces are (-1, 0, 1), (1, 0, 1)).
  const glm::vec3 ridge{0, 0, 1}, left = glm::normalize(glm::vec3(-1, 0, 2)), right = glm::normalize(glm::vec3(1, 0, 2));
  const std::vector<glm::vec3> nrm{left, ridge, ridge, left, right, right};
  const std::vector<std::uint32_t> tris{0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2};
  const std::vector<std::uint32_t> lod{0, 2, 3, 1, 4, 5};
  const FlatFaces f = flat_faces(pos, nrm, {tris, lod});
  ASSERT_EQ(f.lists.size(), 2u);
  std::vector<glm::vec3> all_pos = pos, all_nrm = nrm;
  for (std::size_t c = 0; c < f.copied_from.size(); ++c) all_pos.push_back(pos[f.copied_from[c]]), all_nrm.push_back(f.copy_normals[c]);
  for (std::size_t l = 0; l < 2; ++l) {
    const auto& orig = l == 0 ? tris : lod;
    ASSERT_EQ(f.lists[l].size(), orig.size());
    for (std::size_t t = 0; t < orig.size(); t += 3) {
      const std::uint32_t* ft = &f.lists[l][t];
      EXPECT_TRUE(same_triangle(&orig[t], ft, pos, all_pos)) << "list " << l << " triangle " << t / 3;
      EXPECT_GT(glm::dot(all_nrm[ft[2]], face(pos, orig[t], orig[t + 1], orig[t + 2])), 0.9999f) << "list " << l << " triangle " << t / 3;
    }
  }
  // Two faces (left and right), each given one copy shared by both its triangles and by the LOD's.
  EXPECT_EQ(f.copied_from.size(), 2u);

  const std::vector<glm::vec3> hard(pos.size(), glm::vec3(0, 0, 1));
  const std::vector<glm::vec3> quad{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  const std::vector<std::uint32_t> qt{0, 1, 2, 0, 2, 3};
  const FlatFaces q = flat_faces(quad, hard, {qt});
  EXPECT_TRUE(q.copied_from.empty());
  EXPECT_EQ(q.lists[0], qt);  // every last corner already has the face's normal: unchanged
}

// Applied to a primitive: copies appended (full records, normal replaced), the original lists and
// vertices unchanged, the Flat lists on every level; a skinned primitive gets none.
TEST(FlatGeometry, PrimitiveKeepsItsOwnListsAndVertices) {
  Primitive p = engine::test::quad_primitive(0);
  for (std::size_t v = 0; v < 4; ++v) {  // tilt the corner normals apart: a smooth cushion
    p.vertices[v * 6 + 3] = v % 2 ? 0.3f : -0.3f;
    p.vertices[v * 6 + 4] = v < 2 ? -0.3f : 0.3f;
  }
  p.lods.push_back({0.1f, 0.5f, {0, 1, 2}, {}});
  const Primitive before = p;
  const std::uint32_t added = prepare_flat_geometry(p);
  EXPECT_EQ(added, 1u);  // both triangles (and the LOD's) face +z: one copy of a corner with (0, 0, 1)
  EXPECT_EQ(p.vertex_count, 5u);
  EXPECT_EQ(p.indices, before.indices);
  EXPECT_EQ(p.lods[0].indices, before.lods[0].indices);
  EXPECT_TRUE(std::equal(before.vertices.begin(), before.vertices.end(), p.vertices.begin()));
  EXPECT_EQ(std::vector<float>(p.vertices.end() - 3, p.vertices.end()), (std::vector<float>{0, 0, 1}));
  ASSERT_EQ(p.flat_indices.size(), 6u);
  ASSERT_EQ(p.lods[0].flat_indices.size(), 3u);
  EXPECT_EQ(p.flat_indices[2], 4u);
  EXPECT_EQ(p.flat_indices[5], 4u);
  EXPECT_EQ(p.lods[0].flat_indices[2], 4u);
  EXPECT_EQ(prepare_flat_geometry(p), 0u);  // already prepared: nothing more

  Primitive skinned = engine::test::quad_primitive(0);
  skinned.layout.push_back({AttributeSemantic::Joints0, -1, 4, 6});
  skinned.stride = 10;
  skinned.vertices.assign(40, 0.0f);
  EXPECT_EQ(prepare_flat_geometry(skinned), 0u);
  EXPECT_TRUE(skinned.flat_indices.empty());
}
