// The unit tests prove the programs are valid GLSL ES 3.00 to glslang; this proves a real driver
// (Mesa llvmpipe through EGL surfaceless, GLES 3.0) compiles and links them, and that the metadata
// the runtime relies on is true there: attribute locations, and every listed uniform and sampler is
// active (optimized programs list nothing the driver would drop).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen {
namespace {

class GlContext : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) return;
    display_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, nullptr, nullptr)) return;
    eglBindAPI(EGL_OPENGL_ES_API);
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    ready_ = context_ != EGL_NO_CONTEXT &&
             eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
  }
  static void TearDownTestSuite() {
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    if (display_ != EGL_NO_DISPLAY) eglTerminate(display_);
  }
  void SetUp() override {
    // Mesa EGL is a declared dependency (scripts/install-deps): its absence is a failure, not a skip.
    ASSERT_TRUE(ready_) << "no EGL surfaceless GLES 3 context (install libegl-mesa0)";
  }

  static GLuint compile(GLenum type, const std::string& src, std::string& log) {
    GLuint s = glCreateShader(type);
    const char* text = src.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char buf[4096] = {};
      glGetShaderInfoLog(s, sizeof buf, nullptr, buf);
      log += buf;
    }
    return s;
  }

  // Links `p` and checks its metadata against the driver.
  static void check(const Program& p, const std::string& what) {
    SCOPED_TRACE(what);
    std::string log;
    GLuint vs = compile(GL_VERTEX_SHADER, p.vertex_source, log);
    GLuint fs = compile(GL_FRAGMENT_SHADER, p.fragment_source, log);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
      char buf[4096] = {};
      glGetProgramInfoLog(prog, sizeof buf, nullptr, buf);
      log += buf;
    }
    EXPECT_TRUE(ok) << log << "\n" << p.vertex_source << "\n" << p.fragment_source;
    if (ok) {
      for (const auto& a : p.attributes)
        EXPECT_EQ(glGetAttribLocation(prog, a.name.c_str()), a.location) << a.name;
      if (p.optimized) {
        for (const auto& u : p.uniforms)
          EXPECT_NE(glGetUniformLocation(prog, u.name.c_str()), -1) << u.name;
        for (const auto& s : p.samplers)
          EXPECT_NE(glGetUniformLocation(prog, s.name.c_str()), -1) << s.name;
      }
    }
    glDeleteProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  }

  static inline EGLDisplay display_ = EGL_NO_DISPLAY;
  static inline EGLContext context_ = EGL_NO_CONTEXT;
  static inline bool ready_ = false;
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

TEST_F(GlContext, GeneratedProgramsLinkWithTrueAttributeLocations) {
  for (const auto& f : sample_sets()) check(generate(f), f.key());
  check(generate_uber(), "uber");
}

TEST_F(GlContext, OptimizedProgramsLinkAndEveryListedUniformIsActive) {
  ConstantValues c;
  c.set(UniformSemantic::RoughnessFactor, {0.5f});
  c.set(UniformSemantic::Exposure, {1.0f});
  c.set(UniformSemantic::NormalScale, {1.0f});
  c.set(UniformSemantic::LightRange, 1, {0.0f});
  for (const auto& f : sample_sets()) check(optimize(generate(f), c), f.key() + " optimized");
  check(optimize(generate_uber(), {}), "uber optimized");
}

}  // namespace
}  // namespace meter::shadergen
