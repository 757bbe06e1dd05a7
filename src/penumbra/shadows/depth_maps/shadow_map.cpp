#include "penumbra/shadows/depth_maps/shadow_map.hpp"

#include <chrono>
#include <cmath>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra {

FaceSelect parse_face_select(const std::string& name) {
  if (name == "front") return FaceSelect::front;
  if (name == "back") return FaceSelect::back;
  if (name == "both") return FaceSelect::both;
  throw Error("unknown face selection '" + name + "' (front, back, both)");
}

std::vector<OptionSpec> depth_map_option_specs() {
  return {
      {"resolution", OptionType::integer, "2048", "depth map side in texels", {}, 16, 16384},
      {"faces",
       OptionType::choice,
       "front",
       "caster faces in the map, seen from the light",
       {"front", "back", "both"}},
      {"bias", OptionType::real, "0", "constant depth bias, world units", {}, 0, 1e6},
      {"slope_bias",
       OptionType::real,
       "0.5",
       "slope-scaled bias, texels of depth slope",
       {},
       0,
       1e3},
  };
}

DepthMapSettings DepthMapSettings::from(const MethodOptions& o) {
  return {o.get_int("resolution"), parse_face_select(o.get_choice("faces")), o.get_real("bias"),
          o.get_real("slope_bias")};
}

DepthMap DepthMapSettings::render_from_light_centre(const ShadowContext& ctx,
                                                    StageTimes& times) const {
  const auto start = std::chrono::steady_clock::now();
  DepthMap map = receiver_fitted_depth_map(ctx, hard_shadow_point(ctx.light), resolution, faces);
  times.add("depth_map", elapsed_ms(start));
  return map;
}

DepthMap receiver_fitted_depth_map(const ShadowContext& ctx, const Vec3& light_point,
                                   int resolution, FaceSelect faces) {
  std::vector<Vec3> cover;
  for (size_t i = 0; i < ctx.gbuffer.pixel_count(); ++i)
    if (ctx.receivers[i] == kActive) cover.push_back(ctx.gbuffer.shadow_origin(i));
  DepthMapSpec spec;
  spec.resolution = resolution;
  spec.faces = faces;
  return render_depth_map(ctx.scene, light_point, cover, spec);
}

bool ShadowMapLookup::setup(const DVec3& p, const DVec3& n) {
  if (!map_.project(p, sx_, sy_, depth_)) return false;
  // Slope-scaled term: depth change across one texel on a receiver tilted by θ from the light ray.
  const DVec3 to_light = glm::normalize(map_.proj.eye - p);
  const double cos_t = std::clamp(std::abs(glm::dot(n, to_light)), 1e-3, 1.0);
  const double tan_t = std::min(std::sqrt(1.0 - cos_t * cos_t) / cos_t, 100.0);
  bias_ = bias_constant_ + bias_slope_ * map_.texel_tan * depth_ * tan_t;
  plane_num_ = glm::dot(n, p - map_.proj.eye);
  // n · (ray direction through texel centre (i, j)) is affine in (i, j): its three coefficients
  // once here leave two multiply-adds per tap (Projection::direction expanded).
  const Projection& proj = map_.proj;
  const double w = proj.width, h = proj.height;
  const double n_right = proj.tan_half_x * glm::dot(n, proj.right);
  const double n_up = proj.tan_half_y * glm::dot(n, proj.up);
  den_di_ = 2.0 * n_right / w;
  den_dj_ = -2.0 * n_up / h;
  den0_ = glm::dot(n, proj.forward) + (1.0 / w - 1.0) * n_right + (1.0 - 1.0 / h) * n_up;
  return true;
}

double ShadowMapLookup::plane_depth(int i, int j) const {
  // Ray from the light through the texel centre, with unit forward component: depth = t.
  const double den = den0_ + i * den_di_ + j * den_dj_;
  const double t = plane_num_ / den;
  // Grazing or behind: fall back to the receiver's own depth.
  if (!(std::abs(den) > 1e-12) || !(t > 0.0) || t > 4.0 * depth_ || t < 0.25 * depth_)
    return depth_;
  return t;
}

bool ShadowMapLookup::blocked(int i, int j) const {
  const float stored = map_.at(i, j);
  return stored < plane_depth(i, j) - bias_;
}

float ShadowMapLookup::blocker_depth(int i, int j) const {
  return blocked(i, j) ? map_.at(i, j) : kInfinity;
}

namespace {

class ShadowMap final : public ShadowMethod {
 public:
  explicit ShadowMap(const MethodOptions& o)
      : map_(DepthMapSettings::from(o)), pcf_(o.get_int("pcf")) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    const DepthMap map = map_.render_from_light_centre(ctx, vis.times);
    auto start = std::chrono::steady_clock::now();
    const int k = pcf_;
    const double half = 0.5 * (k - 1);
    parallel_rows(g.height, [&](int y) {
      ShadowMapLookup look(map, map_.bias, map_.slope_bias);
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (ctx.receivers[i] != kActive) continue;
        if (!look.setup(DVec3(g.shadow_origin(i)), DVec3(g.geo_normal[i]))) continue;
        int blocked = 0;
        for (int ty = 0; ty < k; ++ty)
          for (int tx = 0; tx < k; ++tx)
            blocked += look.blocked(static_cast<int>(std::floor(look.sx() + tx - half)),
                                    static_cast<int>(std::floor(look.sy() + ty - half)));
        vis.lit[i] = 1.0f - static_cast<float>(blocked) / static_cast<float>(k * k);
      }
    });
    vis.times.add("lookup", elapsed_ms(start));
    vis.counters["map_texel_tan"] = map.texel_tan;
    return vis;
  }

 private:
  DepthMapSettings map_;
  int pcf_;
};

}  // namespace

void register_shadow_map(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "shadow_map";
  info.summary =
      "hard shadows from a light-centre depth map, constant + slope-scaled bias, k×k PCF; "
      "alpha-textured (perforated) occluders count as opaque";
  info.reference = "[Forest 2008 §2.2.2; Valient 2005 §1; Reeves 1987]";
  info.options = depth_map_option_specs();
  info.options.push_back({"pcf",
                          OptionType::integer,
                          "1",
                          "PCF kernel: k×k texel taps (1 = plain shadow map)",
                          {},
                          1,
                          31});
  info.create = [](const MethodOptions& o) { return std::make_unique<ShadowMap>(o); };
  registry.add(std::move(info));
}

}  // namespace penumbra
