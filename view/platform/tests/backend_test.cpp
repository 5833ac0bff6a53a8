// Both backends must create a context here (EGL surfaceless and OSMesa on llvmpipe); these tests
// run, they never skip.
#include <gtest/gtest.h>

#include <cmath>

#include "gl_test_util.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/gpu_timer.hpp"
#include "meter/platform/render_target.hpp"

namespace mp = meter::platform;
using mp::BackendKind;

class BackendTest : public ::testing::TestWithParam<BackendKind> {};

INSTANTIATE_TEST_SUITE_P(Both, BackendTest, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

TEST_P(BackendTest, CreatesContextAndReportsVersion) {
  auto backend = mp::create_backend(GetParam());
  ASSERT_NE(backend, nullptr);
  EXPECT_EQ(backend->kind(), GetParam());
  EXPECT_EQ(backend->name(), mp::to_string(GetParam()));
  const mp::GlInfo& info = backend->gl().info;
  std::printf("%s\n", backend->renderer_info().c_str());
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_NE(backend->renderer_info().find(info.version), std::string::npos);
  if (GetParam() == BackendKind::Egl) {
    EXPECT_TRUE(info.is_gles);
    EXPECT_EQ(info.version.rfind("OpenGL ES ", 0), 0u) << info.version;
    EXPECT_GE(info.major, 3);
    EXPECT_FALSE(info.needs_framebuffer_srgb_enable);
  } else {
    EXPECT_FALSE(info.is_gles);
    EXPECT_GE(info.major * 10 + info.minor, 45) << info.version;  // asked for 4.5 core
    EXPECT_TRUE(info.needs_framebuffer_srgb_enable);
  }
  EXPECT_GE(info.max_samples, 4);
  EXPECT_GE(info.max_texture_size, 2048);
}

TEST_P(BackendTest, Glsl300EsProgramCompilesAndBadShaderGivesTheLog) {
  auto backend = mp::create_backend(GetParam());
  const mp::Gl& gl = backend->gl();
  EXPECT_NO_THROW(mp::test::ColorProgram program(gl));
  try {
    mp::compile_program(gl, "#version 300 es\nvoid main() { gl_Position = vec4(0.0); }\n",
                        "#version 300 es\nprecision highp float;\nout vec4 o;\n"
                        "void main() { o = undefined_thing; }\n",
                        "broken-test-program");
    FAIL() << "expected GlError";
  } catch (const mp::GlError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("broken-test-program"), std::string::npos) << msg;
    EXPECT_NE(msg.find("fragment"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undefined_thing"), std::string::npos) << msg;
  }
}

TEST_P(BackendTest, CheckGlNamesTheError) {
  auto backend = mp::create_backend(GetParam());
  const mp::Gl& gl = backend->gl();
  gl.Enable(0x1234);  // not a capability
  try {
    mp::check_gl(gl, "enable-bogus");
    FAIL() << "expected GlError";
  } catch (const mp::GlError& e) {
    EXPECT_NE(std::string(e.what()).find("enable-bogus: GL_INVALID_ENUM"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(mp::check_gl(gl, "after drain"));
}

TEST_P(BackendTest, GpuTimerMeasuresWork) {
  auto backend = mp::create_backend(GetParam());
  mp::RenderTarget target(*backend, {.width = 256, .height = 256, .samples = 4});
  mp::test::ColorProgram program(backend->gl());
  mp::GpuTimer timer(*backend);
  std::printf("%s timer: %s\n", std::string(backend->name()).c_str(),
              timer.uses_queries() ? "GL_TIME_ELAPSED queries" : "glFinish + CPU clock");
  timer.start();
  for (int i = 0; i < 20; ++i) program.rect_pixels(256, 256, 0, 0, 256, 256, 0.1f * (i % 10), 0.5f, 0.2f, 1.0f);
  const double ms = timer.stop();
  EXPECT_GT(ms, 0.0);
  EXPECT_TRUE(std::isfinite(ms));
  EXPECT_THROW(timer.stop(), std::logic_error);
}

TEST(Backend, ParseKind) {
  EXPECT_EQ(mp::parse_backend_kind("EGL"), BackendKind::Egl);
  EXPECT_EQ(mp::parse_backend_kind("osmesa"), BackendKind::OSMesa);
  EXPECT_EQ(mp::parse_backend_kind("vulkan"), std::nullopt);
}

TEST(Backend, BadOptionsGiveClearErrors) {
  try {
    mp::create_backend(BackendKind::Egl, {.egl_display = "wayland"});
    FAIL() << "expected BackendError";
  } catch (const mp::BackendError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown display option 'wayland'"), std::string::npos) << e.what();
  }
  try {
    mp::create_backend(BackendKind::Egl, {.egl_display = "device:99"});
    FAIL() << "expected BackendError";
  } catch (const mp::BackendError& e) {
    EXPECT_NE(std::string(e.what()).find("libegl-mesa0"), std::string::npos) << e.what();
  }
  try {
    mp::BackendOptions options;
    options.osmesa_major = 2;
    options.osmesa_minor = 1;
    mp::create_backend(BackendKind::OSMesa, options);
    FAIL() << "expected BackendError";
  } catch (const mp::BackendError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3.3"), std::string::npos) << e.what();
  }
  try {
    mp::BackendOptions options;
    options.osmesa_major = 9;
    options.osmesa_minor = 9;
    mp::create_backend(BackendKind::OSMesa, options);
    FAIL() << "expected BackendError";
  } catch (const mp::BackendError& e) {
    EXPECT_NE(std::string(e.what()).find("libosmesa6"), std::string::npos) << e.what();
  }
}

TEST(Backend, EglDeviceDisplayWorks) {
  // Mesa offers a software EGL device here; the device path must render like surfaceless.
  auto backend = mp::create_backend(BackendKind::Egl, {.egl_display = "device"});
  EXPECT_NE(backend->renderer_info().find("device 0"), std::string::npos) << backend->renderer_info();
  mp::RenderTarget target(*backend, {.width = 8, .height = 8, .srgb = false});
  backend->gl().ClearColor(0.0f, 1.0f, 0.0f, 1.0f);
  backend->gl().Clear(GL_COLOR_BUFFER_BIT);
  EXPECT_EQ(target.resolve_and_read(), mp::Image(8, 8, 0, 255, 0, 255));
}
