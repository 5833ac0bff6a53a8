// The reflection probe bake (EEVEE's world probe from the equirectangular image): GL's cube-face
// convention, level 0 as the image seen in each direction, every level a weighted mean (a uniform
// world stays uniform), lobes that widen level by level, and bad sizes refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "meter/convert/environment_probe.hpp"
#include "meter/platform/render_target.hpp"

using meter::bridge::EnvironmentProbe;
using meter::convert::bake_environment_probe;
using meter::convert::cube_texel_direction;
using meter::platform::Image;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The direction through the centre of equirect texel (x, y) (Blender's mapping, as the ambient
// cube integrates it: row 0 straight up, u = 0.5 + atan2(z, x) / 2pi).
glm::dvec3 equirect_direction(int x, int y, int width, int height) {
  const double lat = (0.5 - (y + 0.5) / height) * kPi, phi = ((x + 0.5) / width - 0.5) * 2.0 * kPi;
  return {std::cos(lat) * std::cos(phi), std::sin(lat), std::cos(lat) * std::sin(phi)};
}

template <typename F>
Image image_of(int width, int height, F colour) {
  Image im(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::ivec3 c = colour(x, y);
      std::uint8_t* p = im.pixel(x, y);
      p[0] = std::uint8_t(c.r), p[1] = std::uint8_t(c.g), p[2] = std::uint8_t(c.b), p[3] = 255;
    }
  return im;
}

const std::uint8_t* texel(const EnvironmentProbe& p, int level, int face, int x, int y) {
  std::size_t offset = 0;
  for (int l = 0; l < level; ++l) offset += 6u * 3u * std::size_t(p.face_size >> l) * std::size_t(p.face_size >> l);
  const std::size_t n = std::size_t(p.face_size >> level);
  return &p.rgb[offset + ((std::size_t(face) * n + std::size_t(y)) * n + std::size_t(x)) * 3u];
}

// Standard deviation of linear luma over one face of one level.
double face_spread(const EnvironmentProbe& p, int level, int face) {
  const int n = p.face_size >> level;
  double sum = 0, sum2 = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v = meter::platform::srgb_to_linear(texel(p, level, face, x, y)[1] / 255.0);
      sum += v, sum2 += v * v;
    }
  const double mean = sum / (n * n);
  return std::sqrt(std::max(0.0, sum2 / (n * n) - mean * mean));
}

}  // namespace

// OpenGL ES 3.0 table 3.21: face +X maps (s, t) to (-z, -y), so its first texel looks up and
// towards +Z; -Z's first texel looks up and towards +X; +Y's first row looks towards -Z.
TEST(EnvironmentProbe, TexelDirectionsFollowGlCubeFaces) {
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    const glm::vec3 centre = cube_texel_direction(f, 3, 3, 7);  // the middle texel of an odd face
    EXPECT_NEAR(glm::distance(centre, axes[f]), 0.0f, 1e-6f) << f;
  }
  const glm::vec3 px = cube_texel_direction(0, 0, 0, 64), nz = cube_texel_direction(5, 0, 0, 64),
                  py = cube_texel_direction(2, 0, 0, 64);
  EXPECT_TRUE(px.y > 0 && px.z > 0) << px.y << " " << px.z;
  EXPECT_TRUE(nz.y > 0 && nz.x > 0) << nz.y << " " << nz.x;
  EXPECT_TRUE(py.z < 0 && py.x < 0) << py.z << " " << py.x;
  // Around the horizon the faces join edge to edge: +X's last column meets -Z's first, -Z's last
  // meets -X's first, -X's last +Z's first and +Z's last +X's first, within a texel.
  const int n = 64, ring[5] = {0, 5, 1, 4, 0};
  const float texel_angle = float(kPi / 2.0 / n);
  for (int i = 0; i < 4; ++i)
    for (int y = 0; y < n; y += 9) {
      const float gap = std::acos(std::min(1.0f, glm::dot(cube_texel_direction(ring[i], n - 1, y, n), cube_texel_direction(ring[i + 1], 0, y, n))));
      EXPECT_LT(gap, 1.5f * texel_angle) << "faces " << ring[i] << " -> " << ring[i + 1] << " row " << y;
    }
}

// Level 0 is the image seen in each texel's direction: a world whose colour encodes its own
// direction (sRGB of (d + 1) / 2) comes back as each texel's direction, within the bilinear
// reading of a 256 x 128 image (3 levels).
TEST(EnvironmentProbe, LevelZeroIsTheWorldInEachTexelsDirection) {
  const int w = 256, h = 128;
  const Image world = image_of(w, h, [&](int x, int y) {
    const glm::dvec3 d = equirect_direction(x, y, w, h);
    return glm::ivec3(glm::round((d + 1.0) * 0.5 * 255.0));
  });
  // Encoded as plain bytes: decode the probe's sRGB back to the same bytes.
  const EnvironmentProbe p = bake_environment_probe(world, 32);
  int worst = 0;
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const glm::dvec3 d(cube_texel_direction(f, x, y, 32));
        const std::uint8_t* t = texel(p, 0, f, x, y);
        for (int k = 0; k < 3; ++k) {
          // The probe stores sRGB of the linear radiance; the image's bytes are sRGB too.
          const int expected = int(std::lround((d[k] + 1.0) * 0.5 * 255.0));
          worst = std::max(worst, std::abs(int(t[k]) - expected));
        }
      }
  EXPECT_LE(worst, 3);
}

// Every level is a normalised weighted mean: a uniform world is the same colour everywhere, to
// the rounding of one sRGB step.
TEST(EnvironmentProbe, UniformWorldStaysUniformAtEveryLevel) {
  const Image world = image_of(32, 16, [](int, int) { return glm::ivec3(200, 120, 40); });
  const EnvironmentProbe p = bake_environment_probe(world, 64);
  ASSERT_EQ(p.levels, 4);
  ASSERT_EQ(p.rgb.size(), EnvironmentProbe::byte_size(64, 4));
  for (int l = 0; l < p.levels; ++l)
    for (int f = 0; f < 6; ++f)
      for (int y = 0; y < (64 >> l); y += 3)
        for (int x = 0; x < (64 >> l); x += 3) {
          const std::uint8_t* t = texel(p, l, f, x, y);
          EXPECT_NEAR(t[0], 200, 1) << l << " " << f;
          EXPECT_NEAR(t[1], 120, 1) << l << " " << f;
          EXPECT_NEAR(t[2], 40, 1) << l << " " << f;
        }
}

// EEVEE's schedule: level 1 (alpha (1/6)^4 = 0.0008) is still the sharp world; each level after
// it blurs more, and the last two (alpha 0.48 and 1) have almost no detail left. A checkerboard of 45 degree
// cells on the face looking at the horizon.
TEST(EnvironmentProbe, LobesWidenLevelByLevel) {
  const Image world = image_of(64, 32, [](int x, int y) { return ((x / 8 + y / 8) % 2) ? glm::ivec3(255) : glm::ivec3(0); });
  const EnvironmentProbe p = bake_environment_probe(world, 512);
  ASSERT_EQ(p.levels, 7);
  double spread[7];
  for (int l = 0; l < 7; ++l) spread[l] = face_spread(p, l, 0);
  EXPECT_GT(spread[0], 0.4);  // black and white cells: 0.5 for a perfect checker
  EXPECT_NEAR(spread[1], spread[0], 0.05 * spread[0]);
  for (int l = 2; l < 6; ++l) EXPECT_LT(spread[l], spread[l - 1]) << "level " << l;
  // The last two levels read coarse mips through 128 samples: what is left is their sampling
  // noise (measured 0.016 and 0.024), not the cells.
  EXPECT_LT(spread[5], 0.1 * spread[0]);
  EXPECT_LT(spread[6], 0.1 * spread[0]);
}

// A world finer than the probe is read at the probe's resolution, as EEVEE renders it into its
// cube: a checkerboard of one-pixel cells (256 x 128) in 8 px faces is grey, not aliased.
TEST(EnvironmentProbe, WorldFinerThanTheProbeIsFilteredNotAliased) {
  const Image world = image_of(256, 128, [](int x, int y) { return ((x + y) % 2) ? glm::ivec3(255) : glm::ivec3(0); });
  const EnvironmentProbe p = bake_environment_probe(world, 8);
  ASSERT_EQ(p.levels, 1);
  for (int f = 0; f < 6; ++f) EXPECT_LT(face_spread(p, 0, f), 0.02) << "face " << f;
  // Linear mean of black and white: 0.5, sRGB 188.
  EXPECT_NEAR(texel(p, 0, 0, 3, 3)[1], 188, 2);
}

TEST(EnvironmentProbe, RefusesSizesItCannotBake) {
  const Image world = image_of(8, 4, [](int, int) { return glm::ivec3(9); });
  for (int bad : {0, 4, 100, 8192}) {
    try {
      bake_environment_probe(world, bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("face size " + std::to_string(bad) + "; expected a power of two in 8..4096"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(bake_environment_probe(Image(1, 1), 8), std::invalid_argument);
}
