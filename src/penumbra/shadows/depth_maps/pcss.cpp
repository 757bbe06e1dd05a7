// `pcss`: percentage-closer soft shadows (Fernando 2005), the approximate baseline every seed
// method is compared with. From the light-centre depth map (depth_maps/shadow_map.hpp):
//  1. blocker search: the depth-map region the light, seen from the receiver, covers at the
//     nearest caster depth z_min — half-width ½·w_light·(z_r − z_min)/(z_r·z_min) in tangent units
//     — sampled on a B×B grid; the blockers' mean depth z_b;
//  2. penumbra width from similar triangles [Fernando 2005 eq. 1]:
//     w_penumbra = w_light·(z_r − z_b)/z_b at the receiver, i.e. a filter half-width of
//     ½·w_light·(z_r − z_b)/(z_r·z_b) in the map (the light's footprint on the blocker plane);
//  3. variable-size PCF over that region with a P×P tap grid.
// w_light: the rectangle's longer side, a disk's or sphere's diameter (option light_size
// overrides). The depth test is the receiver-plane test of depth_maps/shadow_map.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "penumbra/core/parallel.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/depth_maps/shadow_map.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra {

double pcss_light_width(const Light& light) {
  switch (light.shape) {
    case LightShape::point:
      return 0.0;
    case LightShape::rect:
      return std::max(glm::length(light.edge_u), glm::length(light.edge_v));
    case LightShape::disk:
    case LightShape::sphere:
      return 2.0 * light.radius;
  }
  return 0.0;
}

namespace {

class Pcss final : public ShadowMethod {
 public:
  explicit Pcss(const MethodOptions& o)
      : map_(DepthMapSettings::from(o)),
        blocker_(o.get_int("blocker_samples")),
        pcf_(o.get_int("pcf_samples")),
        max_radius_(o.get_real("max_radius")),
        light_size_(o.get_real("light_size")) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    const DepthMap map = map_.render_from_light_centre(ctx, vis.times);
    auto start = std::chrono::steady_clock::now();
    const double w_light = light_size_ > 0.0 ? light_size_ : pcss_light_width(ctx.light);
    const double z_min = std::max(static_cast<double>(map.min_depth), 1e-9);
    parallel_rows(g.height, [&](int y) {
      ShadowMapLookup look(map, map_.bias, map_.slope_bias);
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (ctx.receivers[i] != kActive) continue;
        if (!look.setup(DVec3(g.shadow_origin(i)), DVec3(g.geo_normal[i]))) continue;
        const double z_r = look.depth();
        // 1. Blocker search.
        const double search =
            std::clamp(0.5 * w_light * std::max(z_r - z_min, 0.0) / (z_r * z_min) / map.texel_tan,
                       0.5, max_radius_);
        double sum = 0.0;
        int found = 0;
        for (int by = 0; by < blocker_; ++by)
          for (int bx = 0; bx < blocker_; ++bx) {
            const double ox = ((bx + 0.5) / blocker_ * 2.0 - 1.0) * search;
            const double oy = ((by + 0.5) / blocker_ * 2.0 - 1.0) * search;
            const float d = look.blocker_depth(static_cast<int>(std::floor(look.sx() + ox)),
                                               static_cast<int>(std::floor(look.sy() + oy)));
            if (d < kInfinity) {
              sum += d;
              ++found;
            }
          }
        if (found == 0) continue;  // no blocker: lit
        const double z_b = sum / found;
        // 2. Penumbra width → filter half-width in texels.
        const double radius =
            std::clamp(0.5 * w_light * std::max(z_r - z_b, 0.0) / (z_r * z_b) / map.texel_tan, 0.5,
                       max_radius_);
        // 3. PCF.
        int blocked = 0;
        for (int py = 0; py < pcf_; ++py)
          for (int px = 0; px < pcf_; ++px) {
            const double ox = ((px + 0.5) / pcf_ * 2.0 - 1.0) * radius;
            const double oy = ((py + 0.5) / pcf_ * 2.0 - 1.0) * radius;
            blocked += look.blocked(static_cast<int>(std::floor(look.sx() + ox)),
                                    static_cast<int>(std::floor(look.sy() + oy)));
          }
        vis.lit[i] = 1.0f - static_cast<float>(blocked) / static_cast<float>(pcf_ * pcf_);
      }
    });
    vis.times.add("filter", elapsed_ms(start));
    vis.counters["light_width"] = w_light;
    return vis;
  }

 private:
  DepthMapSettings map_;
  int blocker_, pcf_;
  double max_radius_, light_size_;
};

}  // namespace

void register_pcss(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "pcss";
  info.summary =
      "percentage-closer soft shadows: blocker search, penumbra width from light size, variable "
      "PCF; alpha-textured (perforated) occluders count as opaque";
  info.reference = "[Fernando 2005 eq. 1; Forest 2008 §2.2.2]";
  info.options = depth_map_option_specs();
  info.options.insert(
      info.options.end(),
      {
          {"blocker_samples", OptionType::integer, "6", "blocker search: B×B taps", {}, 1, 64},
          {"pcf_samples", OptionType::integer, "8", "filter: P×P taps", {}, 1, 64},
          {"max_radius",
           OptionType::real,
           "64",
           "largest search/filter half-width, texels",
           {},
           0.5,
           4096},
          {"light_size",
           OptionType::real,
           "0",
           "light width, world units (0: from the light)",
           {},
           0,
           1e6},
      });
  info.create = [](const MethodOptions& o) { return std::make_unique<Pcss>(o); };
  registry.add(std::move(info));
}

}  // namespace penumbra
