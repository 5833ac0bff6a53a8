#include <gtest/gtest.h>

#include <cmath>

#include "meter/engine/evaluation/animation.hpp"
#include "anim_sampling.hpp"

using namespace meter::engine;
using meter::engine::testing::at;
using meter::engine::testing::make;

namespace {

// Quaternion (x,y,z,w) for a rotation of `deg` about Z.
std::vector<float> qz(double deg) {
  const double h = deg * M_PI / 360.0;
  return {0.0f, 0.0f, float(std::sin(h)), float(std::cos(h))};
}

double angle_z(const std::array<float, 4>& q) { return 2.0 * std::atan2(q[2], q[3]) * 180.0 / M_PI; }

}  // namespace

TEST(AnimationSample, LinearScalarInsideAndClampedOutside) {
  auto s = make(Interpolation::Linear, 1, {1.0f, 3.0f}, {10.0f, 30.0f});
  EXPECT_FLOAT_EQ(at(s, 2.0)[0], 20.0f);
  EXPECT_FLOAT_EQ(at(s, 0.0)[0], 10.0f);   // before the first key
  EXPECT_FLOAT_EQ(at(s, 99.0)[0], 30.0f);  // after the last key
  EXPECT_FLOAT_EQ(at(s, std::nan(""))[0], 10.0f);  // NaN time never produces NaN
}

TEST(AnimationSample, SingleKeyIsConstant) {
  auto s = make(Interpolation::Linear, 3, {0.5f}, {1.0f, 2.0f, 3.0f});
  for (double t : {-1.0, 0.5, 7.0}) {
    auto v = at(s, t);
    EXPECT_FLOAT_EQ(v[0], 1.0f);
    EXPECT_FLOAT_EQ(v[2], 3.0f);
  }
}

TEST(AnimationSample, DuplicateKeyTimesTakeTheLaterKeyWithoutDivisionByZero) {
  auto s = make(Interpolation::Linear, 1, {0.0f, 1.0f, 1.0f, 2.0f}, {0.0f, 10.0f, 20.0f, 30.0f});
  EXPECT_FLOAT_EQ(at(s, 0.5)[0], 5.0f);
  EXPECT_FLOAT_EQ(at(s, 1.0)[0], 20.0f);  // at the jump: the later key
  EXPECT_FLOAT_EQ(at(s, 1.5)[0], 25.0f);
  auto c = make(Interpolation::CubicSpline, 1, {0.0f, 1.0f, 1.0f}, {0, 0, 0, 0, 10, 0, 0, 20, 0});
  EXPECT_TRUE(std::isfinite(at(c, 1.0)[0]));
}

TEST(AnimationSample, StepHoldsTheKeyAtOrBefore) {
  auto s = make(Interpolation::Step, 1, {0.0f, 1.0f, 2.0f}, {5.0f, 6.0f, 7.0f});
  EXPECT_FLOAT_EQ(at(s, 0.999)[0], 5.0f);
  EXPECT_FLOAT_EQ(at(s, 1.0)[0], 6.0f);
  EXPECT_FLOAT_EQ(at(s, 1.5)[0], 6.0f);
  EXPECT_FLOAT_EQ(at(s, 5.0)[0], 7.0f);
}

TEST(AnimationSample, SlerpTakesTheShortPathWhenKeysHaveOppositeSigns) {
  // 170 deg and -170 deg (stored as the NEGATED quaternion of 190 deg): the short way passes 180.
  auto a = qz(170.0);
  auto b = qz(190.0);
  for (auto& x : b) x = -x;  // q and -q are the same rotation
  std::vector<float> out = a;
  out.insert(out.end(), b.begin(), b.end());
  auto s = make(Interpolation::Linear, 4, {0.0f, 1.0f}, out);
  auto mid = at(s, 0.5, true);
  const double ang = std::fmod(angle_z(mid) + 360.0, 360.0);
  EXPECT_NEAR(ang, 180.0, 1e-3);
  const double len = std::sqrt(mid[0] * mid[0] + mid[1] * mid[1] + mid[2] * mid[2] + mid[3] * mid[3]);
  EXPECT_NEAR(len, 1.0, 1e-6);
}

TEST(AnimationSample, SlerpIsUniformInAngle) {
  std::vector<float> out = qz(0.0);
  auto b = qz(120.0);
  out.insert(out.end(), b.begin(), b.end());
  auto s = make(Interpolation::Linear, 4, {0.0f, 2.0f}, out);
  EXPECT_NEAR(angle_z(at(s, 0.5, true)), 30.0, 1e-3);
  EXPECT_NEAR(angle_z(at(s, 1.0, true)), 60.0, 1e-3);
}

TEST(AnimationSample, CubicSplineScalesTangentsByTheKeyInterval) {
  // p(t) = t^2 on [0, 2]: values 0 and 4, derivative 0 at t=0 and 4 at t=2. With tangents scaled
  // by the interval (2 s), the Hermite curve reproduces t^2 exactly: p(1) = 1, p(0.5) = 0.25.
  auto s = make(Interpolation::CubicSpline, 1, {0.0f, 2.0f}, {0, 0, 0, /*k1*/ 4, 4, 0});
  EXPECT_NEAR(at(s, 1.0)[0], 1.0, 1e-6);
  EXPECT_NEAR(at(s, 0.5)[0], 0.25, 1e-6);
  EXPECT_NEAR(at(s, 3.0)[0], 4.0, 1e-6);   // clamped after the last key
  EXPECT_NEAR(at(s, -1.0)[0], 0.0, 1e-6);  // clamped before the first
}

TEST(AnimationSample, CubicSplineRotationIsNormalised) {
  std::vector<float> out;
  auto push = [&](std::vector<float> v) { out.insert(out.end(), v.begin(), v.end()); };
  push({0, 0, 0, 0}), push(qz(0)), push({0, 0, 0.3f, 0});
  push({0, 0, 0.3f, 0}), push(qz(90)), push({0, 0, 0, 0});
  auto s = make(Interpolation::CubicSpline, 4, {0.0f, 1.0f}, out);
  auto q = at(s, 0.5, true);
  EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), 1.0, 1e-6);
  EXPECT_GT(angle_z(q), 10.0);
  EXPECT_LT(angle_z(q), 80.0);
}

TEST(AnimationSample, LongLoopingTimesKeepPrecision) {
  // Time in double: one hour in, a 1 ms step still moves a 1-unit-per-second channel.
  auto s = make(Interpolation::Linear, 1, {0.0f, 7200.0f}, {0.0f, 7200.0f});
  const double t = 3600.0;
  EXPECT_NEAR(at(s, t + 0.001)[0] - at(s, t)[0], 0.001, 3e-4);
}

TEST(Pose, WorldMatricesComposeParentBeforeChild) {
  Scene s;
  s.nodes.resize(2);
  s.nodes[0].children = {1};
  s.nodes[0].translation = {1, 0, 0};
  s.nodes[0].scale = {2, 2, 2};
  s.nodes[1].parent = 0;
  s.nodes[1].translation = {0, 1, 0};
  s.roots = {0};
  Pose p = Pose::rest(s);
  std::vector<glm::mat4> w;
  world_matrices(s, p, w);
  EXPECT_FLOAT_EQ(w[1][3].x, 1.0f);
  EXPECT_FLOAT_EQ(w[1][3].y, 2.0f);
}
