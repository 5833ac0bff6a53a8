// Shadow-map projections without GL: every corner of the scene's bounds lands inside the map of a
// directional light; a spot light's axis hits the map's centre and its cone stays inside; lights
// with nothing to cover, point lights and degenerate matrices give no map, never NaN.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "meter/engine/evaluation/shadow_projection.hpp"

using namespace meter::engine;

namespace {

WorldBounds box(glm::vec3 lo, glm::vec3 hi) {
  WorldBounds b;
  b.add(lo), b.add(hi);
  return b;
}

// Texture-space position of `p` in the map (x, y, depth in [0, 1] when inside).
glm::vec3 in_map(const glm::mat4& vp, glm::vec3 p) {
  const glm::vec4 c = shadow_texture_matrix(vp) * glm::vec4(p, 1.0f);
  return glm::vec3(c) / c.w;
}

// A light at `from` whose local -Z points at `to`.
glm::mat4 aimed(glm::vec3 from, glm::vec3 to) { return glm::inverse(glm::lookAt(from, to, glm::vec3(0, 0, 1))); }

bool inside(glm::vec3 t) {
  return t.x >= 0 && t.x <= 1 && t.y >= 0 && t.y <= 1 && t.z >= 0 && t.z <= 1;
}

}  // namespace

TEST(ShadowProjection, DirectionalMapCoversEveryCornerOfTheBounds) {
  Light sun;
  sun.type = LightType::Directional;
  const WorldBounds b = box({-3, -2, -0.6f}, {3, 4, 1.5f});
  const auto vp = shadow_view_projection(sun, aimed({-3.5f, -1.5f, 4.5f}, {0, 0, 0}), b);
  ASSERT_TRUE(vp);
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 c{k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z};
    EXPECT_TRUE(inside(in_map(*vp, c))) << "corner " << k;
  }
  // Nearer the light means smaller depth: a point lifted towards the sun is in front.
  const glm::vec3 dir = glm::normalize(glm::vec3(0, 0, 0) - glm::vec3(-3.5f, -1.5f, 4.5f));
  EXPECT_LT(in_map(*vp, -0.5f * dir).z, in_map(*vp, glm::vec3(0)).z);
}

TEST(ShadowProjection, SpotMapIsCentredOnTheAxisAndHoldsTheCone) {
  Light spot;
  spot.type = LightType::Spot;
  spot.outer_cone = glm::radians(25.0f);
  const glm::vec3 eye{1.0f, -1.4f, 3.4f}, target{-0.3f, 0.2f, -0.62f};
  const auto vp = shadow_view_projection(spot, aimed(eye, target), box({-4, -4, -0.62f}, {4, 4, 1}));
  ASSERT_TRUE(vp);
  const glm::vec3 centre = in_map(*vp, target);
  EXPECT_NEAR(centre.x, 0.5f, 1e-4f);
  EXPECT_NEAR(centre.y, 0.5f, 1e-4f);
  EXPECT_TRUE(inside(centre));
  // A ray 24 degrees off the axis (inside the 25 degree cone) stays inside the map.
  const glm::vec3 axis = glm::normalize(target - eye);
  const glm::vec3 side = glm::normalize(glm::cross(axis, glm::vec3(0, 0, 1)));
  const glm::vec3 off = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(24.0f), side) * glm::vec4(axis, 0.0f));
  EXPECT_TRUE(inside(in_map(*vp, eye + 3.0f * off)));
}

TEST(ShadowProjection, NothingToCoverOrNoMapGivesNone) {
  Light spot;
  spot.type = LightType::Spot;
  EXPECT_FALSE(shadow_view_projection(spot, aimed({0, 0, 5}, {0, 0, 0}), WorldBounds{}));
  // The whole scene behind the light.
  EXPECT_FALSE(shadow_view_projection(spot, aimed({0, 0, 5}, {0, 0, 10}), box({-1, -1, -1}, {1, 1, 1})));
  Light point;
  point.type = LightType::Point;
  EXPECT_FALSE(shadow_view_projection(point, glm::mat4(1.0f), box({-1, -1, -1}, {1, 1, 1})));
  // A zero-scale light node has no direction.
  Light sun;
  EXPECT_FALSE(shadow_view_projection(sun, glm::mat4(0.0f), box({-1, -1, -1}, {1, 1, 1})));
  // A flat (zero-volume) scene still gets a finite map.
  const auto flat = shadow_view_projection(sun, aimed({0.5f, 0, 5}, {0, 0, 0}), box({-1, -1, 0}, {1, 1, 0}));
  ASSERT_TRUE(flat);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite((*flat)[c][r]));
}

TEST(ShadowProjection, BoundsIgnoreNonFinitePoints) {
  WorldBounds b;
  b.add({NAN, 0, 0});
  EXPECT_TRUE(b.empty);
  b.add({1, 2, 3});
  b.add({INFINITY, 0, 0});
  EXPECT_EQ(b.max, glm::vec3(1, 2, 3));
}
