// EEVEE's world probe baked on the CPU: the equirectangular image's linear mip chain, resampled
// into cube faces and GGX-filtered per level as Blender 3.x's lightprobe filter does.
#include "meter/convert/environment_probe.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/platform/render_target.hpp"

namespace meter::convert {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One level of the image in linear light (RGB floats, row 0 = straight up).
struct LinearLevel {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;
  const glm::vec3& at(int x, int y) const { return texels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

// Level 0 decoded from sRGB, then 2 x 2 box averages (as glGenerateMipmap on an sRGB texture, and
// EEVEE's recursive downsample of its probe) down to one texel on the shorter side.
std::vector<LinearLevel> linear_mip_chain(const platform::Image& im) {
  std::array<float, 256> lin{};
  for (int c = 0; c < 256; ++c) lin[std::size_t(c)] = float(platform::srgb_to_linear(c / 255.0));
  std::vector<LinearLevel> chain(1);
  LinearLevel& base = chain[0];
  base.width = im.width, base.height = im.height;
  base.texels.resize(std::size_t(im.width) * std::size_t(im.height));
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const std::uint8_t* p = im.pixel(x, y);
      base.texels[std::size_t(y) * std::size_t(im.width) + std::size_t(x)] = {lin[p[0]], lin[p[1]], lin[p[2]]};
    }
  while (chain.back().width > 1 && chain.back().height > 1) {
    const LinearLevel& src = chain.back();
    LinearLevel dst;
    dst.width = src.width / 2, dst.height = src.height / 2;
    dst.texels.resize(std::size_t(dst.width) * std::size_t(dst.height));
    for (int y = 0; y < dst.height; ++y)
      for (int x = 0; x < dst.width; ++x)
        dst.texels[std::size_t(y) * std::size_t(dst.width) + std::size_t(x)] =
            0.25f * (src.at(2 * x, 2 * y) + src.at(2 * x + 1, 2 * y) + src.at(2 * x, 2 * y + 1) + src.at(2 * x + 1, 2 * y + 1));
    chain.push_back(std::move(dst));
  }
  return chain;
}

// Bilinear read of one level at equirect coordinates (u wraps in longitude, t clamps at the poles).
glm::vec3 bilinear(const LinearLevel& l, double u, double t) {
  const double fx = u * l.width - 0.5, fy = std::clamp(t * l.height - 0.5, 0.0, double(l.height - 1));
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const float ax = float(fx - x0f), ay = float(fy - y0f);
  const int x0 = ((int(x0f) % l.width) + l.width) % l.width, x1 = (x0 + 1) % l.width;
  const int y0 = int(y0f), y1 = std::min(y0 + 1, l.height - 1);
  const glm::vec3 top = glm::mix(l.at(x0, y0), l.at(x1, y0), ax), bottom = glm::mix(l.at(x0, y1), l.at(x1, y1), ax);
  return glm::mix(top, bottom, ay);
}

// Trilinear read in direction d (glTF axes, unit length) with shadergen's equirect_uv mapping
// (Blender's: u = 0.5 + atan2(z, x) / 2pi, t = 0.5 - asin(y) / pi).
glm::vec3 sample(const std::vector<LinearLevel>& chain, const glm::dvec3& d, double lod) {
  const double u = std::abs(d.x) + std::abs(d.z) > 1e-9 ? 0.5 + std::atan2(d.z, d.x) / (2.0 * kPi) : 0.5;
  const double t = 0.5 - std::asin(std::clamp(d.y, -1.0, 1.0)) / kPi;
  lod = std::clamp(lod, 0.0, double(chain.size() - 1));
  const int l0 = int(lod), l1 = std::min(l0 + 1, int(chain.size()) - 1);
  const glm::vec3 a = bilinear(chain[std::size_t(l0)], u, t);
  if (l1 == l0 || lod == double(l0)) return a;
  return glm::mix(a, bilinear(chain[std::size_t(l1)], u, t), float(lod - l0));
}

double radical_inverse_base2(unsigned i) {
  unsigned bits = i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return double(bits) * 2.3283064365386963e-10;
}

// One GGX sample of the lobe around N = V: the half-vector's tangent-space cosine and azimuth.
struct LobeSample {
  double cos_theta, sin_theta, cos_phi, sin_phi, lod;
};

// EEVEE's per-level sample counts (filter quality 1) for levels 1, 2, 3 and beyond.
int sample_count(int level) { return level == 1 ? 32 : level == 2 ? 40 : level == 3 ? 64 : 128; }

// The Hammersley samples of one level's lobe, with the image level each is read from: the lobe's
// share of the sphere per sample, 1 / (n pdf), against an equator texel's solid angle.
std::vector<LobeSample> lobe_samples(double alpha, int n, double texel_solid_angle, double min_lod, double max_lod) {
  const double a2 = alpha * alpha;
  std::vector<LobeSample> out;
  for (int i = 0; i < n; ++i) {
    const double e1 = double(i) / n, phi = 2.0 * kPi * radical_inverse_base2(unsigned(i));
    const double cos_t = std::sqrt((1.0 - e1) / (1.0 + (a2 - 1.0) * e1));
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double k = cos_t * cos_t * (a2 - 1.0) + 1.0;
    const double pdf = a2 / (kPi * k * k) / 4.0;  // D(h) cos / (4 v.h), with n = v: D / 4
    const double lod = std::clamp(0.5 * std::log2(1.0 / (n * pdf) / texel_solid_angle), min_lod, max_lod);
    out.push_back({cos_t, sin_t, std::cos(phi), std::sin(phi), lod});
  }
  return out;
}

// The GGX-weighted mean radiance around n (EEVEE: weight n.l, samples below the horizon skipped).
glm::vec3 filter_lobe(const std::vector<LinearLevel>& chain, const std::vector<LobeSample>& lobe, const glm::dvec3& n) {
  // Blender's make_orthonormal_basis around its up axis (glTF +Y).
  const glm::dvec3 up = std::abs(n.y) < 0.99999 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(up, n)), b = glm::cross(n, t);
  glm::dvec3 sum(0.0);
  double weight = 0.0;
  for (const LobeSample& s : lobe) {
    const glm::dvec3 h = t * (s.sin_theta * s.cos_phi) + b * (s.sin_theta * s.sin_phi) + n * s.cos_theta;
    const glm::dvec3 l = 2.0 * glm::dot(n, h) * h - n;
    const double n_dot_l = glm::dot(n, l);
    if (n_dot_l <= 0.0) continue;
    sum += glm::dvec3(sample(chain, glm::normalize(l), s.lod)) * n_dot_l;
    weight += n_dot_l;
  }
  return weight > 0.0 ? glm::vec3(sum / weight) : glm::vec3(sample(chain, n, 0.0));
}

}  // namespace

glm::vec3 cube_texel_direction(int face, int x, int y, int size) {
  // GL's cube-map selection: face +X reads (s, t) = ((-z / |x| + 1) / 2, (-y / |x| + 1) / 2), and
  // so on per face (OpenGL ES 3.0 table 3.21); row y of the uploaded face is t.
  const float sc = 2.0f * (float(x) + 0.5f) / float(size) - 1.0f, tc = 2.0f * (float(y) + 0.5f) / float(size) - 1.0f;
  glm::vec3 d;
  switch (face) {
    case 0: d = {1.0f, -tc, -sc}; break;
    case 1: d = {-1.0f, -tc, sc}; break;
    case 2: d = {sc, 1.0f, tc}; break;
    case 3: d = {sc, -1.0f, -tc}; break;
    case 4: d = {sc, -tc, 1.0f}; break;
    default: d = {-sc, -tc, -1.0f}; break;
  }
  return glm::normalize(d);
}

bridge::EnvironmentProbe bake_environment_probe(const platform::Image& equirect, int face_size) {
  if (face_size < 8 || face_size > 4096 || (face_size & (face_size - 1)) != 0)
    throw std::invalid_argument("environment probe: face size " + std::to_string(face_size) + "; expected a power of two in 8..4096");
  if (equirect.width < 2 || equirect.height < 2)
    throw std::invalid_argument("environment probe: a " + std::to_string(equirect.width) + "x" + std::to_string(equirect.height) +
                                " image; expected at least 2x2");
  const std::vector<LinearLevel> chain = linear_mip_chain(equirect);
  const double max_lod = double(chain.size() - 1);
  const double texel_solid_angle = (2.0 * kPi / equirect.width) * (kPi / equirect.height);
  bridge::EnvironmentProbe probe;
  probe.face_size = face_size;
  probe.levels = bridge::EnvironmentProbe::levels_for(face_size);
  probe.rgb.reserve(bridge::EnvironmentProbe::byte_size(face_size, probe.levels));
  // The world as EEVEE renders it into the probe: the image read at the mip whose texel matches a
  // level-0 face texel (the sharpest mip when the face is finer than the image). Level 0 is that;
  // the lobes read nothing sharper either (EEVEE filters from that render, not from the image).
  const double base_lod = std::clamp(std::log2(double(equirect.width) / (4.0 * face_size)), 0.0, max_lod);
  for (int level = 0; level < probe.levels; ++level) {
    const int size = face_size >> level;
    std::vector<LobeSample> lobe;
    if (level > 0) {
      const double alpha = std::clamp(std::pow(double(level) / (probe.levels - 1), 4.0), 1e-4, 0.9999);
      lobe = lobe_samples(alpha, sample_count(level), texel_solid_angle, base_lod, max_lod);
    }
    for (int face = 0; face < 6; ++face)
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const glm::dvec3 n(cube_texel_direction(face, x, y, size));
          const glm::vec3 c = level == 0 ? sample(chain, n, base_lod) : filter_lobe(chain, lobe, n);
          for (int k = 0; k < 3; ++k) probe.rgb.push_back(std::uint8_t(platform::linear_to_srgb8(c[k])));
        }
  }
  return probe;
}

}  // namespace meter::convert
