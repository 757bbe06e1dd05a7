// The window: GLFW with an OpenGL 3.3 core context, Dear ImGui on it, one texture for the image.
#pragma once

#include <filesystem>
#include <string>

#include "penumbra/report/report_images.hpp"

struct GLFWwindow;

namespace penumbra::viewer {

/// Where the image is drawn, in window pixels.
struct ImageRect {
  float x = 0, y = 0, width = 0, height = 0;
  bool contains(float px, float py) const {
    return px >= x && py >= y && px < x + width && py < y + height;
  }
};

class GlWindow {
 public:
  /// Throws Error "no display: ..." when no window can be opened (no X server, no OpenGL 3.3).
  GlWindow(int width, int height, const std::string& title);
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;

  bool should_close() const;
  /// Waits for events at most `timeout_s` (0: polls). A worker wakes it with wake().
  void wait_events(double timeout_s);
  static void wake();

  void begin_frame();
  /// Draws the ImGui frame; with `screenshot`, reads the window's pixels to that PNG first.
  void end_frame(const std::filesystem::path* screenshot);

  /// Replaces the image's texture (sRGB bytes, row 0 at the top).
  void set_image(const report::Rgb8Image& picture);
  /// The image drawn as if it had width × height pixels (the full resolution: a preview's smaller
  /// texture is stretched over the same rectangle, so the picture does not jump), at the largest
  /// integer scale that fits `area` (or scaled down to fit), at the area's top-left corner.
  ImageRect draw_image(float area_width, float area_height, int width, int height) const;

 private:
  GLFWwindow* window_ = nullptr;
  unsigned int texture_ = 0;
  bool has_image_ = false;
};

}  // namespace penumbra::viewer
