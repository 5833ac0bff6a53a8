#include "meter/preview/ui_layer.hpp"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

namespace meter::preview {

UiLayer::UiLayer(PreviewWindow& window) : window_(window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the artist's files
  ImGui::StyleColorsDark();
  if (!ImGui_ImplGlfw_InitForOpenGL(static_cast<GLFWwindow*>(window.native_handle()), true) ||
      !ImGui_ImplOpenGL3_Init("#version 300 es")) {
    ImGui::DestroyContext();
    throw platform::BackendError("Dear ImGui cannot start on the window's OpenGL ES context");
  }
  const auto& gl = window_.gpu().gl();
  while (gl.GetError() != GL_NO_ERROR) {
  }
}

UiLayer::~UiLayer() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void UiLayer::begin_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void UiLayer::end_frame() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  const auto& gl = window_.gpu().gl();
  while (gl.GetError() != GL_NO_ERROR) {
  }
}

}  // namespace meter::preview
