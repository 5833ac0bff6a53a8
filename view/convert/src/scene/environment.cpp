// The world environment: the equirectangular image named in the default scene's extras, baked into
// the reflection probe (environment_probe.cpp), and the ambient cube integrated from it for the
// programs' diffuse ambient term.
#include <cmath>
#include <filesystem>

#include "convert_context.hpp"
#include "meter/convert/environment_probe.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::convert {

void validate_environment(ConvertContext& ctx, std::size_t scene) {
  const tinygltf::Value& extras = ctx.m.scenes[scene].extras;
  const std::string p = idx("scenes", scene) + ".extras.";
  if (!extras.IsObject()) return;
  const bool has_file = extras.Has("meter_environment"), has_strength = extras.Has("meter_environment_strength");
  if (has_strength) {
    const tinygltf::Value& v = extras.Get("meter_environment_strength");
    const double k = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
    if (!v.IsNumber() || !std::isfinite(k) || k < 0.0 || k > 1e6) {
      ctx.error(p + "meter_environment_strength", "expected a finite number >= 0 (Blender's Background strength)");
    } else {
      ctx.environment.strength = static_cast<float>(k);
    }
    if (!has_file) ctx.error(p + "meter_environment_strength", "given without meter_environment (the image it scales)");
  }
  if (!has_file) return;
  const tinygltf::Value& v = extras.Get("meter_environment");
  if (!v.IsString() || v.Get<std::string>().empty()) {
    ctx.error(p + "meter_environment", "expected the file name of an equirectangular PNG, relative to the glTF file");
    return;
  }
  ctx.environment.name = v.Get<std::string>();
  const std::filesystem::path file = std::filesystem::path(ctx.file).parent_path() / ctx.environment.name;
  try {
    ctx.environment.image = platform::read_png(file);
  } catch (const platform::ImageError& e) {
    ctx.error(p + "meter_environment", "cannot use \"" + ctx.environment.name + "\": " + e.what());
    return;
  }
  // Two texels per axis at least (the ambient cube and the mip chain need an image), and within
  // what a package stores.
  if (ctx.environment.image.width < 2 || ctx.environment.image.height < 2 || ctx.environment.image.width > 16384 || ctx.environment.image.height > 16384) {
    ctx.error(p + "meter_environment", file.string() + ": " + std::to_string(ctx.environment.image.width) + "x" +
                                       std::to_string(ctx.environment.image.height) + " pixels; expected 2..16384 per side");
    ctx.environment.image = {};
  }
}

// EEVEE's world ambient cube (shadergen kAmbientCube): for each signed axis a, the cosine-weighted
// mean of the map's linear radiance over the hemisphere around a, sum L max(0, d.a) dw / sum
// max(0, d.a) dw, with the texel directions of shadergen's equirect_uv (Blender's mapping).

std::array<glm::vec3, 6> ambient_cube(const platform::Image& im, float strength) {
  constexpr double kPi = 3.14159265358979323846;
  std::array<double, 256> lin{};
  for (int c = 0; c < 256; ++c) lin[std::size_t(c)] = platform::srgb_to_linear(c / 255.0);
  const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  glm::dvec3 sum[6] = {};
  double weight[6] = {};
  for (int y = 0; y < im.height; ++y) {
    const double lat = (0.5 - (y + 0.5) / im.height) * kPi;  // row 0 = straight up (t = 0)
    const double solid_angle = std::cos(lat);                  // per texel, up to a constant
    for (int x = 0; x < im.width; ++x) {
      const double phi = ((x + 0.5) / im.width - 0.5) * 2.0 * kPi;
      const glm::dvec3 d(std::cos(lat) * std::cos(phi), std::sin(lat), std::cos(lat) * std::sin(phi));
      const std::uint8_t* px = im.pixel(x, y);
      const glm::dvec3 radiance(lin[px[0]], lin[px[1]], lin[px[2]]);
      for (int a = 0; a < 6; ++a) {
        const double w = std::max(0.0, glm::dot(d, axes[a])) * solid_angle;
        sum[a] += radiance * w;
        weight[a] += w;
      }
    }
  }
  std::array<glm::vec3, 6> out{};
  for (int a = 0; a < 6; ++a) out[std::size_t(a)] = glm::vec3(sum[a] / std::max(weight[a], 1e-12) * double(strength));
  return out;
}


void convert_environment(const ConvertContext& ctx, Scene& s) {
  if (ctx.environment.image.empty()) return;
  // Specular: EEVEE's prefiltered cube probe baked from the image (the image itself is not
  // packed: nothing at run time reads it). Diffuse: its ambient cube.
  s.environment.probe = bake_environment_probe(ctx.environment.image, kEnvironmentProbeFaceSize);
  s.environment.strength = ctx.environment.strength;
  s.environment.irradiance = ambient_cube(ctx.environment.image, ctx.environment.strength);
}

}  // namespace meter::convert
