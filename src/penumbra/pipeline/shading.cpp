#include "penumbra/pipeline/shading.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/core/parallel.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/light_weights.hpp"

namespace penumbra {

namespace {

const Vec3 kBackgroundRadiance(0.05f, 0.06f, 0.08f);

/// Radiance × cosθ_receiver × cosθ_light / r² toward `light_point`, times the light-side
/// area element (the caller multiplies by the sample's area).
Vec3 geometry_term(const Light& light, const LightFrame& f, const Vec3& p, const Vec3& n,
                   const Vec3& light_point, const Vec3& radiance) {
  const Vec3 d = light_point - p;
  const float r2 = glm::dot(d, d);
  if (!(r2 > 0.0f)) return Vec3(0.0f);
  const Vec3 w = d / std::sqrt(r2);
  const float cos_r = glm::dot(n, w);
  float cos_l = -glm::dot(f.emit_normal, w);
  if (light.two_sided || light.shape == LightShape::sphere) cos_l = std::abs(cos_l);
  if (cos_r <= 0.0f || cos_l <= 0.0f) return Vec3(0.0f);
  return radiance * (cos_r * cos_l / r2);
}

Vec3 sample_radiance(const Scene& scene, const Light& light, Vec2 light_uv) {
  if (!light.is_textured()) return light.radiance;
  return light.radiance * scene.textures[light.emission_texture].sample_rgb(light_uv);
}

float frame_area(const LightFrame& f) {
  return glm::length(glm::cross(f.edge_u, f.edge_v));
}

}  // namespace

std::string_view to_string(ShadingMode mode) {
  return mode == ShadingMode::modulate ? "modulate" : "integrate";
}

RowShader::RowShader(const Frame& frame, const std::vector<const Visibility*>& per_light,
                     ShadingMode mode)
    : frame_(&frame), per_light_(per_light), mode_(mode), exposure_(auto_exposure(frame)) {
  // Computed once per frame and light, shared by every method.
  for (size_t l = 0; l < frame.scene().lights.size(); ++l)
    unshadowed_.push_back(&frame.unshadowed(l));
}

void RowShader::row(int y, Vec3* out) const {
  const Frame& frame = *frame_;
  const Scene& scene = frame.scene();
  const GBuffer& g = frame.gbuffer();
  std::vector<Vec2> light_uv;
  for (int x = 0; x < g.width; ++x) {
    const size_t i = static_cast<size_t>(y) * g.width + x;
    if (g.is_background(i)) {
      out[x] = kBackgroundRadiance * exposure_;
      continue;
    }
    const Vec3 albedo = scene.material_of(scene.meshes[g.mesh_id[i]]).albedo;
    Vec3 irradiance(0.0f);
    for (size_t l = 0; l < scene.lights.size(); ++l) {
      if (frame.receivers(l)[i] != kActive) continue;
      const Visibility& vis = *per_light_[l];
      const Light& light = scene.lights[l];
      if (mode_ == ShadingMode::integrate && vis.masks && light.shape != LightShape::point) {
        // Forest 2008 eq. 4.6: E = (A / N) Σ_s V_s L_s cosθ cosθ' / r².
        const Vec3 p = g.shadow_origin(i);
        const LightFrame f = light_frame(light, p);
        light_uv.resize(frame.samples().count());
        frame.samples().pixel_samples(x, y, light_uv);
        Vec3 sum(0.0f);
        int emitting = 0;
        for (int s = 0; s < frame.samples().count(); ++s) {
          if (!f.emits(light_uv[s])) continue;
          ++emitting;
          if (vis.masks->blocked(i, s)) continue;
          sum += geometry_term(light, f, p, g.shading_normal[i], f.point(light_uv[s]),
                               sample_radiance(scene, light, light_uv[s]));
        }
        if (emitting > 0)
          irradiance += sum * (frame_area(f) * f.uv_area() / static_cast<float>(emitting));
      } else {
        const Vec3 visible = vis.lit_rgb ? (*vis.lit_rgb)[i] : Vec3(vis.lit[i]);
        irradiance += visible * (*unshadowed_[l])[i];
      }
    }
    const Vec3 radiance = albedo * (irradiance / static_cast<float>(kPi) + scene.ambient);
    out[x] = radiance * exposure_;
  }
}

Image<Vec3> shade(const Frame& frame, const std::vector<const Visibility*>& per_light,
                  ShadingMode mode) {
  const RowShader shader(frame, per_light, mode);
  const GBuffer& g = frame.gbuffer();
  Image<Vec3> out(g.width, g.height);
  parallel_rows(g.height, [&](int y) { shader.row(y, &out(0, y)); });
  return out;
}

float auto_exposure(const Frame& frame) {
  const GBuffer& g = frame.gbuffer();
  const Scene& scene = frame.scene();
  // Unshadowed luminance on a sparse pixel grid; its 95th percentile maps to 0.85.
  std::vector<float> lum;
  const int step = std::max(1, std::min(g.width, g.height) / 64);
  for (int y = 0; y < g.height; y += step)
    for (int x = 0; x < g.width; x += step) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (g.is_background(i)) continue;
      Vec3 e(0.0f);
      for (size_t l = 0; l < scene.lights.size(); ++l) e += frame.unshadowed(l)[i];
      const Vec3 albedo = scene.material_of(scene.meshes[g.mesh_id[i]]).albedo;
      lum.push_back(luminance(albedo * (e / static_cast<float>(kPi) + scene.ambient)));
    }
  if (lum.empty()) return 1.0f;
  const size_t k = lum.size() * 95 / 100;
  std::nth_element(lum.begin(), lum.begin() + static_cast<long>(k), lum.end());
  const float level = lum[k];
  return level > 0.0f ? 0.85f / level : 1.0f;
}

}  // namespace penumbra
