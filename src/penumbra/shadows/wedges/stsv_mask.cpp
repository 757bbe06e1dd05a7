#include "penumbra/shadows/wedges/stsv_mask.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/wedges/dcs_counters.hpp"
#include "penumbra/shadows/wedges/stsv_lookup.hpp"

namespace penumbra::stsv {

Summary subtract_stsv_occlusion(const ShadowContext& ctx, const wedge_pass::PixelSetup& setup,
                                Perforated perforated, Image<float>& vis, Image<Vec3>* lit_rgb) {
  using wedge_pass::kTile;
  const auto start = std::chrono::steady_clock::now();
  const StsvSet set = build_stsv(ctx, setup, std::move(perforated));
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  const int n = ctx.samples.count();
  const Texture* emission = light.is_textured() && lit_rgb && !lit_rgb->empty()
                                ? &wedge_pass::emission_texture(ctx.scene, light, "stsv")
                                : nullptr;
  const bool round = light.shape == LightShape::disk || light.shape == LightShape::sphere;
  auto emits = [&](const Vec2& uv) {
    const Vec2 d = uv - Vec2(0.5f);
    return !round || glm::dot(d, d) <= 0.25f;  // LightFrame::emits of a round light
  };
  dcs::SampleSet shared;  // samples sorted into bands of v (dcs_counters.hpp)
  if (!ctx.samples.per_pixel()) shared.assign(ctx.samples.shared_samples(), ctx.samples.k(), emits);
  const int tiles_y = (g.height + kTile - 1) / kTile;
  std::vector<StsvStats> rows(tiles_y);
  if (!set.empty()) {
    parallel_rows(tiles_y, [&](int ty) {
      StsvStats& st = rows[ty];
      std::vector<Vec2> uv(n);
      dcs::SampleSet own;
      std::vector<float> sample_vis(n);
      std::vector<uint8_t> flags(n);
      for (int tx = 0; tx < set.tiles_x; ++tx) {
        const std::vector<uint32_t>& bin = set.bin_of_tile(tx, ty);
        if (bin.empty()) continue;
        for (int y = ty * kTile; y < std::min(g.height, (ty + 1) * kTile); ++y) {
          for (int x = tx * kTile; x < std::min(g.width, (tx + 1) * kTile); ++x) {
            const size_t i = static_cast<size_t>(y) * g.width + x;
            if (ctx.receivers[i] != kActive) continue;
            const Vec3 origin = g.shadow_origin(i);
            const DVec3 p(origin);
            LightFrame f;
            LightProjection lp;
            bool framed = false, has_lp = false;
            const dcs::SampleSet* ss = &shared;
            bool ready = false, any = false;
            for (const uint32_t k : bin) {
              ++st.volume_tests;
              if (!set.volumes[k].contains(p)) continue;
              if (!framed) {  // the light as seen from p, once a volume holds it
                f = light_frame(light, origin);
                has_lp =
                    make_light_projection(p, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), lp);
                framed = true;
              }
              Pair pr;
              const STriangle& t = set.triangles[k];
              if (!make_pair(t, p, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v),
                             has_lp ? &lp : nullptr, pr))
                continue;
              ++st.pairs;
              if (!ready) {  // the pixel's samples, all visible (a cleared LS_buffer)
                if (ctx.samples.per_pixel()) {
                  ctx.samples.pixel_samples(x, y, uv);
                  own.assign(uv, ctx.samples.k(), emits);
                  ss = &own;
                }
                std::fill(sample_vis.begin(), sample_vis.end(), 1.0f);
                ready = true;
              }
              int first = 0, last = 0;
              ss->range(pr.v_lo, pr.v_hi, first, last);
              float* sv = sample_vis.data() + first;
              const float tr = t.transmittance;  // an opaque texel clears the bit (tr = 0)
              const int count = last - first;
              const int crossing = blocked_samples(pr, t, ss->u.data() + first,
                                                   ss->v.data() + first, count, flags.data());
              st.lookups += static_cast<uint64_t>(crossing);
              if (crossing == 0) continue;
              uint64_t blocked = 0;
              for (int s = 0; s < count; ++s) {
                sv[s] = flags[s] ? sv[s] * tr : sv[s];
                blocked += flags[s];
              }
              st.blocked += blocked;
              any |= blocked > 0;
            }
            if (!any) continue;
            // The STSV V_coef [§5.2.1, App. 5.B: the bit count over the emitting samples].
            if (emission) {
              const SampleWeights w = accumulate_sample_weights(f, emission, light.radiance, ss->uv,
                                                                std::span<const float>(sample_vis));
              const Vec3 seen = w.visible_fraction_rgb();
              Vec3& rgb = (*lit_rgb)[i];
              rgb = glm::clamp(rgb - (Vec3(1.0f) - seen), Vec3(0.0f), Vec3(1.0f));
              vis[i] = std::clamp(vis[i] - (1.0f - w.visible_fraction()), 0.0f, 1.0f);
              continue;
            }
            float seen = 0.0f;
            int total = 0;
            for (int s = 0; s < n; ++s) {
              seen += ss->emit[s] ? sample_vis[s] : 0.0f;
              total += ss->emit[s];
            }
            if (total > 0) vis[i] = std::clamp(vis[i] - (1.0f - seen / total), 0.0f, 1.0f);
          }
        }
      }
    });
  }
  StsvStats total;
  for (const StsvStats& r : rows) total += r;
  return summarize(set, total, elapsed_ms(start));
}

}  // namespace penumbra::stsv
