// The mouse on the image: drag to orbit the camera around its target, right-drag (or shift-drag)
// to pan, the wheel to zoom, ctrl-drag to move the light parallel to the image plane.
#include <imgui.h>

#include <cmath>

#include "viewer.hpp"

namespace penumbra::viewer {

namespace {

constexpr float kOrbitDegPerPixel = 0.4f;

}  // namespace

void Viewer::handle_mouse() {
  ImGuiIO& io = ImGui::GetIO();
  const bool over_image =
      !io.WantCaptureMouse && image_rect_.contains(io.MousePos.x, io.MousePos.y);
  for (int b = 0; b < 2; ++b)
    if (over_image && ImGui::IsMouseClicked(b)) drag_button_ = b;
  if (drag_button_ >= 0 && !ImGui::IsMouseDown(drag_button_)) drag_button_ = -1;
  if (over_image && io.MouseWheel != 0.0f) {
    state_.camera.zoom(std::pow(0.9f, io.MouseWheel));
    edited();
  }
  if (drag_button_ < 0 || (io.MouseDelta.x == 0.0f && io.MouseDelta.y == 0.0f)) return;
  const float dx = io.MouseDelta.x, dy = io.MouseDelta.y;
  const Camera cam = state_.camera.camera();
  // World units per window pixel at the distance of the target (or of the light).
  const float pixels = std::max(image_rect_.height, 1.0f);
  const float tan_half = std::tan(cam.vfov_deg * static_cast<float>(kPi) / 360.0f);
  if (io.KeyCtrl) {
    LightEdit& light = state_.lights[static_cast<size_t>(light_)];
    const Vec3 forward = glm::normalize(cam.target - cam.position);
    const Vec3 right = glm::normalize(glm::cross(forward, cam.up));
    const Vec3 up = glm::cross(right, forward);
    const float per_pixel = 2.0f * tan_half * glm::length(light.center - cam.position) / pixels;
    light.center += per_pixel * (dx * right - dy * up);
  } else if (drag_button_ == 1 || io.KeyShift) {
    const float per_pixel = 2.0f * tan_half / pixels;  // in distances to the target
    state_.camera.pan(-dx * per_pixel, dy * per_pixel);
  } else {
    state_.camera.orbit(-dx * kOrbitDegPerPixel, dy * kOrbitDegPerPixel);
  }
  edited();
}

}  // namespace penumbra::viewer
