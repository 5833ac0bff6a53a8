// GLFW window with an OpenGL ES 3 context created through EGL (GLFW_EGL_CONTEXT_API +
// GLFW_OPENGL_ES_API): the same API, driver and GL function table path as the offscreen EGL
// backend, so the engine's generated programs compile and draw the same way in the window.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>
#include <utility>

#include "meter/platform/gl_api.hpp"
#include "meter/preview/preview_window.hpp"

namespace meter::preview {
namespace {

std::string last_glfw_error() {
  const char* text = nullptr;
  const int code = glfwGetError(&text);
  if (code == GLFW_NO_ERROR) return "no GLFW error text";
  return text ? text : "GLFW error " + std::to_string(code);
}

void* glfw_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

// The window's context seen by the engine: an EGL OpenGL ES context, like the offscreen backend's,
// but with the window surface as its default framebuffer.
class WindowGpu final : public platform::GpuBackend {
 public:
  explicit WindowGpu(GLFWwindow* window) : window_(window) {
    make_current();
    gl_ = platform::load_gl(&glfw_proc, "egl-window", /*is_gles=*/true);
  }
  platform::BackendKind kind() const override { return platform::BackendKind::Egl; }
  std::string_view name() const override { return "egl-window"; }
  const platform::Gl& gl() const override { return gl_; }
  std::string renderer_info() const override {
    return "egl-window: " + gl_.info.version + " | " + gl_.info.renderer + " | " + gl_.info.glsl_version +
           " | GLFW " + glfwGetVersionString();
  }
  void make_current() override { glfwMakeContextCurrent(window_); }

 private:
  GLFWwindow* window_;
  platform::Gl gl_;
};

class GlfwWindow final : public PreviewWindow {
 public:
  GlfwWindow(WindowSize size, const std::string& title) {
    if (!glfwInit()) {
      throw platform::BackendError("cannot start GLFW (" + last_glfw_error() +
                                   "); is DISPLAY (X11) or WAYLAND_DISPLAY set? Under no display, run it "
                                   "in xvfb-run -a (Debian xvfb)");
    }
    glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_ES_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window_ = glfwCreateWindow(size.width, size.height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      const std::string why = last_glfw_error();
      glfwTerminate();
      throw platform::BackendError("cannot open a " + std::to_string(size.width) + "x" +
                                   std::to_string(size.height) + " window with an OpenGL ES 3 context through EGL (" +
                                   why + "); install libegl-mesa0 and libgles2");
    }
    glfwSetWindowPos(window_, 0, 0);
    watch_activity();
    try {
      gpu_ = std::make_unique<WindowGpu>(window_);
    } catch (...) {
      glfwDestroyWindow(window_);
      glfwTerminate();
      throw;
    }
    glfwSwapInterval(0);
  }

  ~GlfwWindow() override {
    gpu_.reset();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }

  platform::GpuBackend& gpu() override { return *gpu_; }
  WindowSize framebuffer_size() const override {
    WindowSize s;
    glfwGetFramebufferSize(window_, &s.width, &s.height);
    return s;
  }
  void resize(WindowSize size) override { glfwSetWindowSize(window_, size.width, size.height); }
  void poll_events(double timeout_s) override {
    if (timeout_s > 0) {
      glfwWaitEventsTimeout(timeout_s);
    } else {
      glfwPollEvents();
    }
  }
  bool close_requested() const override { return glfwWindowShouldClose(window_) != 0; }
  bool take_activity() override { return std::exchange(activity_, false); }

  platform::Image read_back(int x, int y, int width, int height) override {
    const auto& gl = gpu_->gl();
    const WindowSize fb = framebuffer_size();
    platform::Image image(width, height);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    // GL rows run bottom-up from the framebuffer's bottom edge; the box is given from the top.
    gl.ReadPixels(x, fb.height - y - height, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    platform::check_gl(gl, "meter-preview: reading the window's framebuffer");
    const std::size_t row = static_cast<std::size_t>(width) * 4;
    for (int r = 0; r < height / 2; ++r) {
      std::swap_ranges(image.rgba.begin() + static_cast<std::ptrdiff_t>(r * row),
                       image.rgba.begin() + static_cast<std::ptrdiff_t>((r + 1) * row),
                       image.rgba.begin() + static_cast<std::ptrdiff_t>((height - 1 - r) * row));
    }
    return image;
  }

  void present() override { glfwSwapBuffers(window_); }
  void* native_handle() override { return window_; }

 private:
  // Installed before the UI layer's: Dear ImGui's GLFW backend chains to these callbacks.
  void watch_activity() {
    glfwSetWindowUserPointer(window_, this);
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double, double) { mark(w); });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int, int, int) { mark(w); });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double) { mark(w); });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int, int, int, int) { mark(w); });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned) { mark(w); });
    glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int) { mark(w); });
    glfwSetCursorEnterCallback(window_, [](GLFWwindow* w, int) { mark(w); });
    glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { mark(w); });
    glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { mark(w); });
  }
  static void mark(GLFWwindow* w) { static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w))->activity_ = true; }

  GLFWwindow* window_ = nullptr;
  std::unique_ptr<WindowGpu> gpu_;
  bool activity_ = true;
};

}  // namespace

std::unique_ptr<PreviewWindow> create_glfw_window(WindowSize size, const std::string& title) {
  return std::make_unique<GlfwWindow>(size, title);
}

}  // namespace meter::preview
