#include "gl_window.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/io/image_io.hpp"

namespace penumbra::viewer {

namespace {

std::string& glfw_message() {
  static std::string message;
  return message;
}

void on_glfw_error(int /*code*/, const char* description) {
  glfw_message() = description ? description : "unknown GLFW error";
}

}  // namespace

GlWindow::GlWindow(int width, int height, const std::string& title) {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    throw Error("no display: cannot open a window (" + glfw_message() +
                "; scripts can run under xvfb-run)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw Error("no display: cannot open an OpenGL 3.3 window (" + glfw_message() + ")");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini written beside the user's files
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  glGenTextures(1, &texture_);
}

GlWindow::~GlWindow() {
  glDeleteTextures(1, &texture_);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool GlWindow::should_close() const {
  return glfwWindowShouldClose(window_);
}

void GlWindow::wait_events(double timeout_s) {
  if (timeout_s <= 0.0)
    glfwPollEvents();
  else
    glfwWaitEventsTimeout(timeout_s);
}

void GlWindow::wake() {
  glfwPostEmptyEvent();
}

void GlWindow::begin_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void GlWindow::set_image(const report::Rgb8Image& picture) {
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  // Nearest when enlarged: pixels stay pixels (a preview's blocks show it is one).
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, picture.width(), picture.height(), 0, GL_RGB,
               GL_UNSIGNED_BYTE, picture.data());
  has_image_ = true;
}

ImageRect GlWindow::draw_image(float area_width, float area_height, int width, int height) const {
  ImageRect r;
  if (!has_image_ || width <= 0 || height <= 0 || area_width <= 0 || area_height <= 0) return r;
  const float fit =
      std::min(area_width / static_cast<float>(width), area_height / static_cast<float>(height));
  const float scale = fit >= 1.0f ? std::floor(fit) : fit;
  r.width = static_cast<float>(width) * scale;
  r.height = static_cast<float>(height) * scale;
  ImGui::GetBackgroundDrawList()->AddImage(
      reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture_)), ImVec2(r.x, r.y),
      ImVec2(r.x + r.width, r.y + r.height));
  return r;
}

void GlWindow::end_frame(const std::filesystem::path* screenshot) {
  ImGui::Render();
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  glViewport(0, 0, width, height);
  glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (screenshot) {
    std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    // OpenGL's rows run bottom to top, the PNG's top to bottom.
    std::vector<uint8_t> flipped(rgb.size());
    const size_t row = static_cast<size_t>(width) * 3;
    for (int y = 0; y < height; ++y)
      std::copy_n(rgb.data() + static_cast<size_t>(height - 1 - y) * row, row,
                  flipped.data() + static_cast<size_t>(y) * row);
    write_png_rgb8(*screenshot, width, height, flipped);
  }
  glfwSwapBuffers(window_);
}

}  // namespace penumbra::viewer
