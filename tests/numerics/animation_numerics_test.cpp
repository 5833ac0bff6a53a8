// Quaternions and animation sampling at the edges (docs/numerics.md, "Quaternions", "Animation").
// Cases already asserted in view/engine/tests/animation_test.cpp are not repeated here (the doc
// names them); these add exact-opposite and nearly-identical slerp, non-unit inputs, every
// interpolation at/after the last key, and looping at 24 h / 7 d / 1 year of uptime.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "meter/engine/evaluation/animation.hpp"
#include "anim_sampling.hpp"

using namespace meter::engine;
using meter::engine::testing::at;
using meter::engine::testing::make;

namespace {

double norm(const std::array<float, 4>& q) {
  return std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
}
// Rotation angle (degrees) between two quaternions, sign- and scale-independent (q ~ -q ~ 2q):
// 2 atan2(|vec(conj(a) b)|, |w(conj(a) b)|), well conditioned for tiny angles (acos is not).
double angle_between(const std::array<float, 4>& a, const std::array<float, 4>& b) {
  const double ax = -a[0], ay = -a[1], az = -a[2], aw = a[3];  // conj(a)
  const double bx = b[0], by = b[1], bz = b[2], bw = b[3];
  const double w = aw * bw - ax * bx - ay * by - az * bz;
  const double x = aw * bx + ax * bw + ay * bz - az * by;
  const double y = aw * by - ax * bz + ay * bw + az * bx;
  const double z = aw * bz + ax * by - ay * bx + az * bw;
  return 2.0 * std::atan2(std::sqrt(x * x + y * y + z * z), std::abs(w)) * 180.0 / std::numbers::pi;
}
std::vector<float> axis_angle(double ax, double ay, double az, double deg) {
  const double l = std::sqrt(ax * ax + ay * ay + az * az), h = deg * std::numbers::pi / 360.0;
  return {float(ax / l * std::sin(h)), float(ay / l * std::sin(h)), float(az / l * std::sin(h)), float(std::cos(h))};
}
std::vector<float> cat(std::vector<float> a, const std::vector<float>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
bool all_finite(const std::array<float, 4>& v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

// Bound: unit length within 1e-6, angle from the start key within 1e-3 deg of u * total.
TEST(Quaternion, SlerpQToMinusQIsTheIdentityPath) {
  const auto q = axis_angle(1, 2, 3, 77);
  std::vector<float> mq(q);
  for (auto& x : mq) x = -x;
  auto s = make(Interpolation::Linear, 4, {0.0f, 1.0f}, cat(q, mq));
  for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    auto r = at(s, t, true);
    ASSERT_TRUE(all_finite(r));
    EXPECT_NEAR(norm(r), 1.0, 1e-6);
    EXPECT_LT(angle_between(r, {q[0], q[1], q[2], q[3]}), 1e-3) << "t=" << t;  // never leaves q
  }
}

// dot > 0.9995 takes the normalised-lerp branch: its error against exact slerp is the chord/arc
// difference, 4.1e-6 deg at most for keys 1.5 deg apart; float keys add ~1e-5 deg. Bound 1e-4 deg,
// and the path stays monotone.
TEST(Quaternion, NearlyIdenticalKeysUseNlerpWithinBound) {
  for (double gap : {1.5, 0.1, 1e-4, 0.0}) {
    const auto a = axis_angle(0, 0, 1, 30), b = axis_angle(0, 0, 1, 30 + gap);
    auto s = make(Interpolation::Linear, 4, {0.0f, 1.0f}, cat(a, b));
    double prev = -1;
    for (int k = 0; k <= 20; ++k) {
      const double u = k / 20.0;
      auto r = at(s, u, true);
      ASSERT_TRUE(all_finite(r));
      EXPECT_NEAR(norm(r), 1.0, 1e-6);
      const double ang = angle_between(r, {a[0], a[1], a[2], a[3]});
      EXPECT_NEAR(ang, u * gap, 1e-4) << "gap " << gap << " u " << u;
      EXPECT_GE(ang + 1e-4, prev);
      prev = ang;
    }
  }
}

// Exactly opposite rotations (180 deg apart, dot = 0): the path is well defined and uniform.
TEST(Quaternion, ExactlyOppositeRotationsInterpolateUniformly) {
  const auto a = axis_angle(0, 1, 0, 0), b = axis_angle(0, 1, 0, 180);
  auto s = make(Interpolation::Linear, 4, {0.0f, 2.0f}, cat(a, b));
  for (int k = 0; k <= 8; ++k) {
    auto r = at(s, k * 0.25, true);
    ASSERT_TRUE(all_finite(r));
    EXPECT_NEAR(norm(r), 1.0, 1e-6);
    EXPECT_NEAR(angle_between(r, {a[0], a[1], a[2], a[3]}), 180.0 * k / 8.0, 1e-3);
  }
}

// Non-unit keys (runtime-built data, or a 1e-3 export error): the result is unit length within
// 1e-6 and has the same direction as slerp of the normalised keys (within 1e-3 deg).
TEST(Quaternion, NonUnitInputsGiveUnitOutput) {
  auto a = axis_angle(1, 0, 0, 10), b = axis_angle(1, 0, 0, 100);
  std::vector<float> a3(a), b7(b);
  for (auto& x : a3) x *= 3.0f;
  for (auto& x : b7) x *= 0.001f;
  auto s = make(Interpolation::Linear, 4, {0.0f, 1.0f}, cat(a3, b7));
  auto ref = make(Interpolation::Linear, 4, {0.0f, 1.0f}, cat(a, b));
  for (double u : {0.0, 0.1, 0.5, 1.0}) {
    auto r = at(s, u, true);
    EXPECT_NEAR(norm(r), 1.0, 1e-6);
    // Weighted by the lengths the blend is not uniform in angle, but it must stay on the arc
    // between the keys (never outside [10, 100] deg) and be exact at the ends.
    const double ang = angle_between(r, {0, 0, 0, 1});
    EXPECT_GE(ang, 10.0 - 1e-3);
    EXPECT_LE(ang, 100.0 + 1e-3);
  }
  EXPECT_LT(angle_between(at(s, 0.0, true), at(ref, 0.0, true)), 1e-3);
  EXPECT_LT(angle_between(at(s, 1.0, true), at(ref, 1.0, true)), 1e-3);
  // All-zero key: no NaN, the identity is used.
  auto z = make(Interpolation::Step, 4, {0.0f}, {0, 0, 0, 0});
  auto r = at(z, 0.0, true);
  EXPECT_EQ(r, (std::array<float, 4>{0, 0, 0, 1}));
}

// CUBICSPLINE rotations with large tangents: every sample is unit length within 1e-6 (a raw
// Hermite blend of unit quaternions is not), across 1000 random key/tangent sets.
TEST(Quaternion, CubicSplineRenormalisedEverywhere) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ax(-1, 1), tan(-5, 5);
  for (int rep = 0; rep < 1000; ++rep) {
    std::vector<float> out;
    for (int k = 0; k < 2; ++k) {
      std::vector<float> in_t, out_t;
      for (int c = 0; c < 4; ++c) in_t.push_back(float(tan(rng))), out_t.push_back(float(tan(rng)));
      out = cat(out, in_t);
      out = cat(out, axis_angle(ax(rng), ax(rng), ax(rng) + 2.5, 360 * ax(rng)));
      out = cat(out, out_t);
    }
    auto s = make(Interpolation::CubicSpline, 4, {0.0f, 0.5f}, out);
    for (double t : {0.05, 0.25, 0.49}) {
      auto r = at(s, t, true);
      ASSERT_TRUE(all_finite(r));
      ASSERT_NEAR(norm(r), 1.0, 1e-6) << rep << " t=" << t;
    }
  }
}

// glTF: before the first key -> first value, after the last -> last value, at the last key
// exactly -> last value (bit-exact, every interpolation).
TEST(Sampling, ClampedOutsideAndExactAtTheLastKeyForEveryInterpolation) {
  for (auto mode : {Interpolation::Linear, Interpolation::Step}) {
    auto s = make(mode, 1, {0.5f, 1.0f, 2.0f}, {3.0f, 7.0f, 11.0f});
    EXPECT_EQ(at(s, -1e9)[0], 3.0f);
    EXPECT_EQ(at(s, 0.5)[0], 3.0f);
    EXPECT_EQ(at(s, 2.0)[0], 11.0f);
    EXPECT_EQ(at(s, std::nextafter(2.0, 0.0))[0], mode == Interpolation::Step ? 7.0f : 11.0f);
    EXPECT_EQ(at(s, 1e300)[0], 11.0f);
    EXPECT_EQ(at(s, INFINITY)[0], 11.0f);
    EXPECT_EQ(at(s, -INFINITY)[0], 3.0f);
    EXPECT_EQ(at(s, NAN)[0], 3.0f);
  }
  // Cubic: (in, value, out) per key; the value, not a tangent, comes back at the ends.
  auto c = make(Interpolation::CubicSpline, 1, {0.0f, 1.0f}, {100, 3, -100, 100, 11, -100});
  EXPECT_EQ(at(c, -5.0)[0], 3.0f);
  EXPECT_EQ(at(c, 1.0)[0], 11.0f);
  EXPECT_EQ(at(c, 5.0)[0], 11.0f);
}

// Duplicate key times in every mode: finite, and the later key wins at the shared time.
TEST(Sampling, DuplicateKeyTimesAreFiniteInEveryMode) {
  for (auto mode : {Interpolation::Linear, Interpolation::Step, Interpolation::CubicSpline}) {
    const bool cubic = mode == Interpolation::CubicSpline;
    std::vector<float> vals = {0, 10, 20, 30};
    std::vector<float> out;
    for (float v : vals) {
      if (cubic) out.push_back(1e30f);
      out.push_back(v);
      if (cubic) out.push_back(1e30f);
    }
    auto s = make(mode, 1, {0.0f, 1.0f, 1.0f, 2.0f}, out);
    for (double t = -0.5; t <= 2.5; t += 0.125) ASSERT_TRUE(std::isfinite(at(s, t)[0])) << int(mode) << " t=" << t;
    EXPECT_EQ(at(s, 1.0)[0], 20.0f) << int(mode);
  }
}

// Single key and STEP for rotations: returned normalised, never interpolated.
TEST(Sampling, SingleKeyRotationIsNormalised) {
  auto s = make(Interpolation::Linear, 4, {3.0f}, {0, 0, 2, 0});
  for (double t : {-1.0, 3.0, 1e9}) EXPECT_EQ(at(s, t, true), (std::array<float, 4>{0, 0, 1, 0}));
}

// CUBICSPLINE tangents scale with the key interval: the same curve shape keyed over 0.001 s and
// over 1000 s gives the same values at the same fraction u (to float precision, 1e-5 relative).
TEST(Sampling, CubicTangentScalingIsIntervalInvariant) {
  for (float len : {0.001f, 1.0f, 1000.0f}) {
    // p(t) = (t/len)^3 over [0, len]: dp/dt = 0 at 0 and 3/len at len.
    auto s = make(Interpolation::CubicSpline, 1, {0.0f, len}, {0, 0, 0, 3.0f / len, 1, 0});
    for (double u : {0.1, 0.5, 0.9}) EXPECT_NEAR(at(s, u * len)[0], u * u * u, 1e-5) << len;
  }
}

// Looping: meter keeps uptime in double seconds and wraps with loop_time() (exact fmod) before
// sampling, so after 24 h, 7 days or 1 year the sample equals the one at t = 0 bit for bit when
// the uptime is a whole number of periods, and a +1 ms offset still moves by exactly 1 ms.
TEST(Looping, LongUptimeGivesTheSameSampleAsTimeZero) {
  // A 1.6 s needle-sweep loop keyed at float times (0.4 s steps are not exact in binary).
  auto s = make(Interpolation::Linear, 1, {0.0f, 0.4f, 0.8f, 1.2f, 1.6f}, {0, 40, 100, 40, 0});
  const double start = s.input.front(), end = s.input.back();
  const double period = end - start;  // the float key time, as a double
  for (double uptime : {86400.0, 7 * 86400.0, 365 * 86400.0}) {
    const double n = std::floor(uptime / period);
    const double t_exact = n * period;  // a whole number of periods
    EXPECT_EQ(loop_time(t_exact, start, end), start) << uptime;
    EXPECT_EQ(at(s, loop_time(t_exact, start, end))[0], at(s, 0.0)[0]);
    // 0.3 s later: the wrapped time is within one double ulp of 1 year (3.7e-9 s) of 0.3.
    const double lt = loop_time(t_exact + 0.3, start, end);
    EXPECT_NEAR(lt, 0.3, 4e-9) << uptime;
    EXPECT_NEAR(at(s, lt)[0], at(s, 0.3)[0], 1e-4);
    // A 1 ms step keeps its full size after a year (a float clock would have 2 s steps by then).
    EXPECT_NEAR(loop_time(t_exact + 0.301, start, end) - lt, 0.001, 1e-8);
  }
  // The 1-year uptime in float would already be quantised to 2 s: why the clock is double.
  EXPECT_EQ(std::nextafter(float(365 * 86400.0), 1e30f) - float(365 * 86400.0), 2.0f);
}

TEST(Looping, EdgesOfLoopTime) {
  EXPECT_EQ(loop_time(NAN, 1.0, 3.0), 1.0);
  EXPECT_EQ(loop_time(INFINITY, 1.0, 3.0), 1.0);
  EXPECT_EQ(loop_time(5.0, 2.0, 2.0), 2.0);    // empty loop
  EXPECT_EQ(loop_time(5.0, 3.0, 1.0), 3.0);    // reversed
  EXPECT_EQ(loop_time(0.5, 1.0, 3.0), 2.5);    // before start: wraps backwards
  EXPECT_EQ(loop_time(3.0, 1.0, 3.0), 1.0);    // the end is the next start
  const double r = loop_time(-1e-300, 0.0, 1.0);  // r + len rounds to len: must stay < end
  EXPECT_GE(r, 0.0);
  EXPECT_LT(r, 1.0);
  for (double t = -10; t < 10; t += 0.37) {
    const double v = loop_time(t, -0.5, 1.25);
    ASSERT_GE(v, -0.5);
    ASSERT_LT(v, 1.25);
  }
}
