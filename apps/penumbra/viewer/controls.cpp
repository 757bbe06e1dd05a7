// The mouse on the image: drag to orbit the camera around its target, right-drag (or shift-drag)
// to pan, the wheel to zoom; drag the light's gizmo (or ctrl-drag anywhere) to move the light
// parallel to the image plane.
#include <imgui.h>

#include <cmath>
#include <optional>

#include "viewer.hpp"

namespace penumbra::viewer {

namespace {

constexpr float kOrbitDegPerPixel = 0.4f;
constexpr float kGizmoRadiusPx = 9.0f;

/// Where `point` appears in the drawn image (window pixels), if it is in front of the camera.
std::optional<ImVec2> project(const Camera& camera, const Vec3& point, const ImageRect& rect) {
  const Camera::RayBasis b = camera.ray_basis();
  const Vec3 d = point - camera.position;
  const float z = glm::dot(d, b.forward);
  if (!(z > 0.0f) || rect.width <= 0.0f) return std::nullopt;
  const float ndc_x = glm::dot(d, b.right) / (z * b.tan_half * b.aspect);
  const float ndc_y = glm::dot(d, b.true_up) / (z * b.tan_half);
  return ImVec2(rect.x + 0.5f * (ndc_x + 1.0f) * rect.width,
                rect.y + 0.5f * (1.0f - ndc_y) * rect.height);
}

}  // namespace

void Viewer::handle_mouse() {
  ImGuiIO& io = ImGui::GetIO();
  Camera cam = state_.camera.camera();
  cam.width = state_.width;
  cam.height = state_.height;
  LightEdit& light = state_.lights[static_cast<size_t>(light_)];
  // The gizmo: in the beauty view only, so that the other views show their values unmasked.
  const std::optional<ImVec2> gizmo =
      mode_ == ViewMode::beauty ? project(cam, light.center, image_rect_) : std::nullopt;
  const bool over_image =
      !io.WantCaptureMouse && image_rect_.contains(io.MousePos.x, io.MousePos.y);
  const auto near_gizmo = [&] {
    if (!gizmo) return false;
    const float dx = io.MousePos.x - gizmo->x, dy = io.MousePos.y - gizmo->y;
    return dx * dx + dy * dy <= 4.0f * kGizmoRadiusPx * kGizmoRadiusPx;
  };
  if (gizmo) {
    const bool hot = drag_light_ || (over_image && near_gizmo());
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    draw->AddCircle(*gizmo, kGizmoRadiusPx,
                    hot ? IM_COL32(255, 220, 80, 255) : IM_COL32(255, 255, 255, 200), 24, 2.0f);
    draw->AddCircleFilled(*gizmo, 2.5f, IM_COL32(255, 220, 80, 255));
  }
  if (!args_.script.empty()) return;  // a script's run takes no input
  for (int button = 0; button < 2; ++button)
    if (over_image && ImGui::IsMouseClicked(button)) {
      drag_button_ = button;
      drag_light_ = button == 0 && (io.KeyCtrl || near_gizmo());
    }
  if (drag_button_ >= 0 && !ImGui::IsMouseDown(drag_button_)) {
    drag_button_ = -1;
    drag_light_ = false;
  }
  if (over_image && io.MouseWheel != 0.0f) {
    state_.camera.zoom(std::pow(0.9f, io.MouseWheel));
    edited();
  }
  if (drag_button_ < 0 || (io.MouseDelta.x == 0.0f && io.MouseDelta.y == 0.0f)) return;
  const float dx = io.MouseDelta.x, dy = io.MouseDelta.y;
  // World units per window pixel, at the distance of the target (or of the light).
  const float pixels = std::max(image_rect_.height, 1.0f);
  const Camera::RayBasis b = cam.ray_basis();
  if (drag_light_) {
    const float depth = glm::dot(light.center - cam.position, b.forward);
    const float per_pixel = 2.0f * b.tan_half * std::abs(depth) / pixels;
    light.center += per_pixel * (dx * b.right - dy * b.true_up);
  } else if (drag_button_ == 1 || io.KeyShift) {
    const float per_pixel = 2.0f * b.tan_half / pixels;  // in distances to the target
    state_.camera.pan(-dx * per_pixel, dy * per_pixel);
  } else {
    state_.camera.orbit(-dx * kOrbitDegPerPixel, dy * kOrbitDegPerPixel);
  }
  edited();
}

}  // namespace penumbra::viewer
