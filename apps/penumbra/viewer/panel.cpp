// The panel at the window's right: method and its options (widgets made from the registry's
// declarations, checked as --set checks them), light, animation, camera, view, times and
// counters, files.
#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "penumbra/core/error.hpp"
#include "viewer.hpp"

namespace penumbra::viewer {

namespace {

constexpr float kPanelWidth = 380.0f;
const ImVec4 kErrorColour(1.0f, 0.45f, 0.4f, 1.0f);

void tooltip(const std::string& text) {
  if (!text.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text.c_str());
}

bool finite_range(const OptionSpec& spec) {
  return spec.min > -1e299 && spec.max < 1e299;
}

/// One typed widget; returns true with the new value's text when the user changed it.
bool option_widget(const OptionSpec& spec, const std::string& current, std::string& out) {
  const char* label = spec.key.c_str();
  switch (spec.type) {
    case OptionType::boolean: {
      bool v = current == "true";
      if (!ImGui::Checkbox(label, &v)) return false;
      out = v ? "true" : "false";
      return true;
    }
    case OptionType::choice: {
      bool changed = false;
      if (ImGui::BeginCombo(label, current.c_str())) {
        for (const std::string& c : spec.choices)
          if (ImGui::Selectable(c.c_str(), c == current)) {
            out = c;
            changed = c != current;
          }
        ImGui::EndCombo();
      }
      return changed;
    }
    case OptionType::integer: {
      long long v = std::atoll(current.c_str());
      const long long lo = static_cast<long long>(std::max(spec.min, -1e18));
      const long long hi = static_cast<long long>(std::min(spec.max, 1e18));
      if (!ImGui::DragScalar(label, ImGuiDataType_S64, &v, 0.2f, &lo, &hi)) return false;
      out = std::to_string(v);
      return true;
    }
    case OptionType::real: {
      double v = std::atof(current.c_str());
      const double lo = spec.min, hi = spec.max;
      const float speed = finite_range(spec)
                              ? static_cast<float>((hi - lo) / 500.0)
                              : static_cast<float>(std::max(std::abs(v), 1.0) * 0.01);
      if (!ImGui::DragScalar(label, ImGuiDataType_Double, &v, speed, &lo, &hi, "%.6g"))
        return false;
      char text[64];
      std::snprintf(text, sizeof text, "%.9g", v);
      out = text;
      return true;
    }
  }
  return false;
}

}  // namespace

bool Viewer::set_option(const std::string& key, const std::string& text, std::string* error) {
  std::map<std::string, std::string> values = state_.options[state_.method];
  values[key] = text;
  try {
    resolve_options(MethodRegistry::builtin().get(state_.method), values);
  } catch (const Error& e) {
    if (error) *error = e.what();
    return false;
  }
  state_.options[state_.method] = values;
  edited();
  return true;
}

void Viewer::choose_method(const std::string& name) {
  if (name == state_.method) return;
  state_.method = name;
  edited();
}

void Viewer::draw_panel() {
  // In ImGui's units, the window's (the framebuffer's pixels differ on a scaled display).
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(size.x - kPanelWidth, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, size.y));
  ImGui::Begin("Penumbra", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(200.0f);
  stats_panel();
  method_panel();
  light_panel();
  animation_panel();
  view_panel();
  files_panel();
  ImGui::PopItemWidth();
  ImGui::End();
}

void Viewer::draw_image() {
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  image_rect_ = window_.draw_image(size.x - kPanelWidth, size.y, state_.width, state_.height);
}

void Viewer::method_panel() {
  if (!ImGui::CollapsingHeader("Method", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (ImGui::BeginCombo("method", state_.method.c_str())) {
    for (const MethodInfo* m : methods_->listed()) {
      if (ImGui::Selectable(m->name.c_str(), m->name == state_.method)) choose_method(m->name);
      tooltip(m->summary + " " + m->reference);
    }
    ImGui::EndCombo();
  }
  int k = state_.samples.k;
  if (ImGui::SliderInt("samples K", &k, 1, 64)) {
    state_.samples.k = k;
    edited();
  }
  tooltip("K×K light samples per pixel (1 = the light centre)");
  const std::string pattern(to_string(state_.samples.pattern));
  if (ImGui::BeginCombo("pattern", pattern.c_str())) {
    for (SamplePattern p : all_sample_patterns())
      if (ImGui::Selectable(std::string(to_string(p)).c_str(), p == state_.samples.pattern)) {
        state_.samples.pattern = p;
        edited();
      }
    ImGui::EndCombo();
  }
  option_widgets();
}

void Viewer::option_widgets() {
  const MethodInfo& info = MethodRegistry::builtin().get(state_.method);
  const auto& set = state_.options[state_.method];
  for (const OptionSpec& spec : info.options) {
    const auto it = set.find(spec.key);
    const std::string current = it == set.end() ? spec.default_value : it->second;
    std::string text;
    if (option_widget(spec, current, text) && set_option(spec.key, text, &option_error_))
      option_error_.clear();
    tooltip(spec.help);
  }
  if (!option_error_.empty()) ImGui::TextColored(kErrorColour, "%s", option_error_.c_str());
}

void Viewer::light_panel() {
  if (!ImGui::CollapsingHeader("Light and camera", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (base_->lights.size() > 1) {
    int l = light_;
    if (ImGui::SliderInt("light", &l, 0, static_cast<int>(base_->lights.size()) - 1)) {
      light_ = l;
      picture_dirty_ = true;
    }
  }
  LightEdit& edit = state_.lights[static_cast<size_t>(light_)];
  const float step = scene_diagonal_ * 0.002f;
  bool changed = ImGui::DragFloat3("centre", &edit.center.x, step, 0.0f, 0.0f, "%.3f");
  changed |=
      ImGui::SliderFloat("size ×", &edit.scale, 0.01f, 10.0f, "%.3f", ImGuiSliderFlags_Logarithmic);
  const char* shapes[] = {"point", "rect", "disk", "sphere"};
  int shape = static_cast<int>(edit.shape);
  if (ImGui::Combo("shape", &shape, shapes, 4)) {
    edit.shape = static_cast<LightShape>(shape);
    changed = true;
  }
  changed |= ImGui::SliderFloat("radiance ×", &edit.intensity, 0.01f, 100.0f, "%.3f",
                                ImGuiSliderFlags_Logarithmic);
  if (ImGui::Button("reset light")) {
    edit = {base_->lights[static_cast<size_t>(light_)].center, 1.0f,
            base_->lights[static_cast<size_t>(light_)].shape, 1.0f};
    changed = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("reset camera")) {
    state_.camera = OrbitCamera(base_->camera);
    changed = true;
  }
  if (changed) edited();
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped(
      "On the image: drag to orbit, right-drag (or shift-drag) to pan, the wheel to zoom; drag "
      "the light's circle (or ctrl-drag) to move the light.");
  ImGui::PopStyleColor();
}

void Viewer::animation_panel() {
  const Animation& a = base_->animation;
  if (a.empty() || !ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (ImGui::Button(state_.playing ? "pause" : "play")) {
    state_.playing = !state_.playing;
    if (!state_.playing) edited();  // settle to the full-resolution frame
  }
  ImGui::SameLine();
  float t = static_cast<float>(state_.time_s);
  if (ImGui::SliderFloat("time (s)", &t, static_cast<float>(a.start_s), static_cast<float>(a.end_s),
                         "%.3f")) {
    state_.time_s = t;
    state_.playing = false;
    edited();
  }
  const int frame = static_cast<int>(std::lround((state_.time_s - a.start_s) * a.fps));
  ImGui::Text("frame %d of 0..%d at %.3g fps; moves%s%s%s", frame, a.frame_count() - 1, a.fps,
              a.moves_geometry() ? " geometry" : "", a.moves_lights() ? " lights" : "",
              a.moves_camera() ? (state_.camera.moved() ? " (camera: yours)" : " camera") : "");
}

void Viewer::view_panel() {
  if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const ViewMode before = mode_;
  for (ViewMode m : {ViewMode::beauty, ViewMode::visibility, ViewMode::error,
                     ViewMode::signed_error, ViewMode::split}) {
    if (ImGui::RadioButton(to_string(m), mode_ == m)) mode_ = m;
    if (m != ViewMode::error && m != ViewMode::split) ImGui::SameLine();
  }
  bool split_changed = false;
  if (mode_ == ViewMode::split)
    for (int i = 0; i < 2; ++i)
      if (ImGui::BeginCombo(i == 0 ? "left" : "right", split_[i].c_str())) {
        for (const MethodInfo* m : methods_->listed())
          if (ImGui::Selectable(m->name.c_str(), m->name == split_[i])) {
            split_[i] = m->name;
            split_changed = true;
          }
        ImGui::EndCombo();
      }
  if (mode_ != before) picture_dirty_ = true;
  if (split_changed || (mode_ != before && (mode_ == ViewMode::split || before == ViewMode::split)))
    edited();
  if (picture_info_.waiting_for_reference) ImGui::TextDisabled("error: computing the reference");
  if (picture_info_.error_scale > 0.0)
    ImGui::Text("error colours saturate at %.4g", picture_info_.error_scale);
}

void Viewer::stats_panel() {
  if (!job_error_.empty() && job_error_generation_ == state_.generation)
    ImGui::TextColored(kErrorColour, "%s", job_error_.c_str());
  if (!shown_) {
    ImGui::Text("computing the first frame...");
    return;
  }
  const RenderOutput& s = *shown_;
  const bool current = s.job.generation == state_.generation;
  for (const MethodResult& r : s.results)
    ImGui::Text("%-14s %9.1f ms", r.method.c_str(), r.total_ms);
  ImGui::Text("%dx%d %s%s, K=%d", s.job.camera.width, s.job.camera.height,
              s.job.preview ? "preview" : "full", current ? "" : " (computing)", s.job.samples.k);
  ImGui::Text("scene %.0f + frame %.0f + shading %.0f ms", s.scene_ms, s.frame_ms, s.shade_ms);
  ImGui::Text("latency %.0f ms (edit to shown)",
              std::chrono::duration<double, std::milli>(s.finished - s.job.submitted).count());
  if (picture_info_.error)
    ImGui::Text("vs %s: mean %.2e  max %.3f  rmse %.2e", reference_label(args_).c_str(),
                picture_info_.error->mean_abs, picture_info_.error->max_abs,
                picture_info_.error->rmse);
  if (!ImGui::CollapsingHeader("Stages and counters")) return;
  for (const MethodResult& r : s.results)
    for (size_t l = 0; l < r.per_light.size(); ++l) {
      const Visibility& v = r.per_light[l];
      ImGui::TextDisabled("%s, light %zu", r.method.c_str(), l);
      for (const auto& [stage, ms] : v.times.stages())
        ImGui::Text("  %-24s %9.2f ms", stage.c_str(), ms);
      for (const auto& [name, value] : v.counters)
        ImGui::Text("  %-24s %12.6g", name.c_str(), value);
    }
}

void Viewer::files_panel() {
  if (!ImGui::CollapsingHeader("Files")) return;
  ImGui::InputText("stem", file_stem_, sizeof file_stem_);
  const bool final = frame_is_final();
  const std::string stem = file_stem_;
  const auto write = [&](const char* label, const std::string& path, auto&& action) {
    if (!ImGui::Button(label)) return;
    try {
      action(path);
      status_ = "wrote " + path;
    } catch (const Error& e) {
      status_ = e.what();
    }
  };
  write("screenshot", stem + ".png", [&](const std::string& p) { screenshot_ = p; });
  ImGui::SameLine();
  if (final) {
    write("visibility", stem + "_visibility.exr",
          [&](const std::string& p) { save_visibility(p); });
    ImGui::SameLine();
    write("scene", stem + ".json", [&](const std::string& p) { save_scene(p); });
  } else {
    ImGui::TextDisabled("(saves wait for the final frame)");
  }
  if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
}

}  // namespace penumbra::viewer
