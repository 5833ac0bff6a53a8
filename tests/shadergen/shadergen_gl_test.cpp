// The unit tests prove the programs are valid GLSL ES 3.00 to glslang; this proves a real driver
// (Mesa llvmpipe through the view's own backends, EGL and OSMesa) compiles and links them, and
// that the metadata the runtime relies on is true there: attribute locations, and every listed
// uniform and sampler is active (optimized programs list nothing the driver would drop).
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"
#include "meter/platform/gl_api.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen {
namespace {

// Both backends the view runs on: EGL (GLES 3.2) and OSMesa (desktop 4.5 core compiling ES 3.00
// through ARB_ES3_compatibility) -- a program one of them rejects would fail on that target only.
class GlContext : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override {
    // Both backends are declared dependencies (scripts/install-deps): their absence is a failure,
    // not a skip; create_backend's message names the package.
    try {
      backend_ = platform::create_backend(GetParam());
    } catch (const platform::BackendError& e) {
      FAIL() << e.what();
    }
  }

  // Links `p` with the view's own compile_program and checks its metadata against the driver.
  void check(const Program& p, const std::string& what) {
    SCOPED_TRACE(what);
    const platform::Gl& gl = backend_->gl();
    GLuint prog = 0;
    try {
      prog = platform::compile_program(gl, p.vertex_source, p.fragment_source, what);
    } catch (const platform::GlError& e) {
      ADD_FAILURE() << e.what() << "\n" << p.vertex_source << "\n" << p.fragment_source;
      return;
    }
    for (const auto& a : p.attributes)
      EXPECT_EQ(gl.GetAttribLocation(prog, a.name.c_str()), a.location) << a.name;
    if (p.optimized) {
      for (const auto& u : p.uniforms) EXPECT_NE(gl.GetUniformLocation(prog, u.name.c_str()), -1) << u.name;
      for (const auto& s : p.samplers) EXPECT_NE(gl.GetUniformLocation(prog, s.name.c_str()), -1) << s.name;
    }
    gl.DeleteProgram(prog);
    EXPECT_EQ(gl.GetError(), static_cast<GLenum>(GL_NO_ERROR));
  }

  std::unique_ptr<platform::GpuBackend> backend_;
};

std::vector<MaterialFeatures> sample_sets() {
  std::vector<MaterialFeatures> out;
  for (int m = 0; m <= static_cast<int>(ShadingModel::PbrMetallicRoughness); ++m)
    for (int variant = 0; variant < 4; ++variant) {
      MaterialFeatures f;
      f.shading = static_cast<ShadingModel>(m);
      f.precision = variant & 1 ? Precision::Mediump : Precision::Highp;
      f.alpha = static_cast<AlphaMode>(variant % 3);
      f.base_color_texture = variant >= 2;
      f.vertex_colors = variant == 1;
      f.vertex_alpha = variant == 3;
      f.double_sided = variant == 2;
      f.lights = {1, variant, variant == 3 ? 2 : 0};
      f.skin_joints = variant == 2 ? kMaxSkinJoints : 0;
      f.morph_targets = variant == 3 ? 3 : 0;
      f.morph_normals = variant == 3;
      const bool per_pixel =
          f.shading == ShadingModel::BlinnPhong || f.shading == ShadingModel::PbrMetallicRoughness;
      if (per_pixel && variant >= 1) {
        f.normal_texture = true;
        f.has_tangents = variant == 2;
        f.environment_map_2d = variant == 3;
        f.occlusion_texture = true;
        f.texcoord1_slots = 1u << static_cast<unsigned>(TextureSlot::Occlusion);
        f.texture_transform = variant == 1;
      }
      if (f.shading == ShadingModel::PbrMetallicRoughness && variant >= 2)
        f.metallic_roughness_texture = f.emissive_texture = true;
      out.push_back(f);
    }
  return out;
}

TEST_P(GlContext, GeneratedProgramsLinkWithTrueAttributeLocations) {
  for (const auto& f : sample_sets()) check(generate(f), meter::shadergen::program_key(f));
  check(generate_uber(), "uber");
}

TEST_P(GlContext, OptimizedProgramsLinkAndEveryListedUniformIsActive) {
  ConstantValues c;
  c.set(UniformSemantic::RoughnessFactor, {0.5f});
  c.set(UniformSemantic::Exposure, {1.0f});
  c.set(UniformSemantic::NormalScale, {1.0f});
  c.set(UniformSemantic::LightRange, 1, {0.0f});
  for (const auto& f : sample_sets()) check(optimize(generate(f), c), meter::shadergen::program_key(f) + " optimized");
  check(optimize(generate_uber(), {}), "uber optimized");
}

INSTANTIATE_TEST_SUITE_P(Backends, GlContext,
                         ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });

}  // namespace
}  // namespace meter::shadergen
