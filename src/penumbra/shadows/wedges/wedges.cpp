#include "penumbra/shadows/wedges/wedges.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/core/stats.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "penumbra/shadows/wedges/stsv_mask.hpp"

namespace penumbra {

namespace {

using namespace wedge_pass;

/// Paper IV §5.1, eq. 1: the coverages c_A, c_B of two silhouette loops combine to
/// max(c_A, c_B) + ½ min(c_A, c_B), folded over the groups in group order.
double overlap_combine(double c, double cg) {
  return std::min(1.0, std::max(c, cg) + 0.5 * std::min(c, cg));
}

/// The RGB side of a textured rectangular light: its emission, the RGB table (coverage
/// = texture) and where the per-channel visible fractions go.
struct RgbLight {
  const LightEmission* emission = nullptr;
  const CoverageTextureRGB* table = nullptr;
  Image<Vec3>* out = nullptr;
};

/// Without the overlap approximation pass 2's sum as one group: group 0 with the layered count
/// at every active pixel (WedgePass2Input).
GroupCounts single_group(const ShadowContext& ctx, const Image<float>& count) {
  GroupCounts gc;
  gc.begin.assign(count.size() + 1, 0);
  for (size_t i = 0; i < count.size(); ++i) {
    if (ctx.receivers[i] == kActive) {
      gc.group.push_back(0);
      gc.value.push_back(count[i]);
    }
    gc.begin[i + 1] = static_cast<uint32_t>(gc.group.size());
  }
  return gc;
}

/// Pass 2 by WedgeOptions::pass2: V (and a textured light's per-channel visible fractions) from
/// the folded per-channel occlusion it returns, as the CPU pass turns its sums into V.
Image<float> device_pass2(const ShadowContext& ctx, const Light& light, const BinnedWedges& bw,
                          const WedgeOptions& options, const Image<float>& count,
                          const GroupCounts& gcount, const RgbLight& rgb,
                          const CoverageTexture* table) {
  const GroupCounts single = options.overlap ? GroupCounts{} : single_group(ctx, count);
  const Image<DVec3> occ =
      options.pass2(ctx, light,
                    WedgePass2Input{bw, options.overlap ? gcount : single, options.overlap,
                                    rgb.out ? rgb.emission : nullptr, table, options.lookup});
  Image<float> vis(ctx.gbuffer.width, ctx.gbuffer.height, 1.0f);
  for (size_t i = 0; i < vis.size(); ++i) {
    if (ctx.receivers[i] != kActive) continue;
    vis[i] = rgb.out ? rgb_visibility(occ[i], rgb.emission->total, (*rgb.out)[i])
                     : static_cast<float>(1.0 - occ[i].x);
  }
  return vis;
}

/// What every (sub-)light of a frame shares: the per-pixel setup and the casters' adjacency.
struct FrameShared {
  PixelSetup setup;
  CasterMeshes casters;
};

/// One light (or sub-light): pass 1, silhouettes, wedges, pass 2. Returns V per pixel.
Image<float> visibility_for_light(const ShadowContext& ctx, const Light& light,
                                  const FrameShared& shared, const WedgeOptions& options,
                                  WedgeStats& st, const RgbLight& rgb = {}) {
  const GBuffer& g = ctx.gbuffer;
  const PixelSetup& setup = shared.setup;
  const Vec3 centre = hard_shadow_point(light);
  // Paper III §3.3: the coverage texture replaces the analytic area for rectangular lights.
  const CoverageTexture* tex =
      options.texture && light.shape == LightShape::rect ? options.table.get() : nullptr;
  auto area = [&](const CoveredEdge& e) {
    return tex ? tex->sector_minus_triangle(e.a, e.b, options.lookup) : e.area;
  };
  // Textured light: the emission-weighted coverage per channel, exact or from the RGB table.
  auto area_rgb = [&](const CoveredEdge& e) {
    return rgb.table ? rgb.table->sector_minus_triangle(e.a, e.b, options.lookup)
                     : weighted_sector_minus_triangle(*rgb.emission, e.a, e.b);
  };

  // Silhouette edges from the light centre [Assarsson 2003 III §3.1], one wedge each. With the
  // overlap approximation, per group (light-facing patch: its silhouette loops, wedges/pass.hpp).
  auto start = std::chrono::steady_clock::now();
  const Casters casters = make_casters(shared.casters, centre);
  const std::vector<WedgeEdge> sil = silhouette_edges(casters, centre);
  st.silhouette_edges += sil.size();
  st.silhouettes_ms += elapsed_ms(start);

  start = std::chrono::steady_clock::now();
  Image<float> count;
  GroupCounts gcount;
  if (options.overlap)
    gcount = group_counts(ctx, casters, centre, &setup.volume);
  else
    count = layered_counts(ctx, casters, centre, &setup.volume);
  st.pass1_ms += elapsed_ms(start);

  // Per pixel with the overlap approximation: the coverage of each group (its hard count plus its
  // wedges, clamped), combined with eq. 1. Groups come in order from both the count entries and
  // the bin (sorted by group).
  auto overlap_pixel = [&](size_t i, const PixelLight* pl, const std::vector<uint32_t>& bin,
                           const BinnedWedges* bw, PassCounters& c) {
    double total = 0.0;
    for_each_group(gcount, i, pl, bin, bw, c,
                   [&](uint32_t, double hard, const std::vector<CoveredEdge>& edges) {
                     double sum = hard;
                     for (const CoveredEdge& e : edges)
                       sum += pl->occlusion(bw->wedges[e.wedge], area(e));
                     total = overlap_combine(total, std::clamp(sum, 0.0, 1.0));
                   });
    return static_cast<float>(1.0 - total);
  };
  // The same per channel (eq. 1 applied to each channel's coverage).
  auto overlap_pixel_rgb = [&](size_t i, const PixelLight* pl, const std::vector<uint32_t>& bin,
                               const BinnedWedges* bw, PassCounters& c) {
    DVec3 total(0.0);
    for_each_group(gcount, i, pl, bin, bw, c,
                   [&](uint32_t, double hard, const std::vector<CoveredEdge>& edges) {
                     DVec3 sum(hard);
                     for (const CoveredEdge& e : edges) {
                       const DVec3 w = area_rgb(e);
                       for (int k = 0; k < 3; ++k)
                         sum[k] += pl->occlusion(bw->wedges[e.wedge], w[k]);
                     }
                     for (int k = 0; k < 3; ++k)
                       total[k] = overlap_combine(total[k], std::clamp(sum[k], 0.0, 1.0));
                   });
    return rgb_visibility(total, rgb.emission->total, (*rgb.out)[i]);
  };

  const std::vector<DVec3> hull = light_hull_points(light);
  if (hull.empty() || sil.empty() || !setup.any_active) {  // point light: hard shadows
    Image<float> vis(g.width, g.height, 1.0f);
    PassCounters unused;
    for (size_t i = 0; i < vis.size(); ++i) {
      if (ctx.receivers[i] != kActive) continue;
      if (rgb.out) {
        vis[i] = options.overlap
                     ? overlap_pixel_rgb(i, nullptr, {}, nullptr, unused)
                     : rgb_visibility(DVec3(count[i]), rgb.emission->total, (*rgb.out)[i]);
        continue;
      }
      vis[i] = options.overlap ? overlap_pixel(i, nullptr, {}, nullptr, unused)
                               : 1.0f - std::clamp(count[i], 0.0f, 1.0f);
    }
    return vis;
  }

  // Wedges, their screen hulls and tile bins.
  start = std::chrono::steady_clock::now();
  const BinnedWedges bw = build_and_bin(ctx, setup, sil, wedge_light(light), options.construction);
  st.wedges += bw.wedges.size();
  st.wedge_fallbacks += bw.degenerate;
  st.wedges_ms += elapsed_ms(start);

  // Pass 2 [Assarsson 2003 III §3.2; Forest 2008 Algorithm 3]: per pixel, every wedge of its tile.
  start = std::chrono::steady_clock::now();
  if (options.pass2 && !(rgb.out && rgb.table)) {
    Image<float> vis = device_pass2(ctx, light, bw, options, count, gcount, rgb, tex);
    st.pass2_ms += elapsed_ms(start);
    st.pass2_on_device = true;
    return vis;
  }
  PassCounters pc;
  Image<float> vis = run_pass2(
      ctx, light, bw, pc,
      [&](size_t i, const PixelLight* pl, const std::vector<uint32_t>& bin, PassCounters& c) {
        if (rgb.out) {
          if (options.overlap) return overlap_pixel_rgb(i, pl, bin, &bw, c);
          // The hard count covers every channel alike; each wedge adds its per-channel coverage.
          DVec3 sum(count[i]);
          if (pl)
            visit_covered(*pl, bw, bin, 0, bin.size(), c, [&](const CoveredEdge& e) {
              const DVec3 w = area_rgb(e);
              for (int k = 0; k < 3; ++k) sum[k] += pl->occlusion(bw.wedges[e.wedge], w[k]);
            });
          return rgb_visibility(sum, rgb.emission->total, (*rgb.out)[i]);
        }
        if (options.overlap) return overlap_pixel(i, pl, bin, &bw, c);
        double sum = count[i];
        if (pl)
          visit_covered(*pl, bw, bin, 0, bin.size(), c, [&](const CoveredEdge& e) {
            sum += pl->occlusion(bw.wedges[e.wedge], area(e));
          });
        return static_cast<float>(1.0 - std::clamp(sum, 0.0, 1.0));
      });
  st.pixel_tests += pc.tests;
  st.pixels_inside += pc.inside;
  st.pixels_covered += pc.covered;
  st.plane_fallbacks += pc.fallbacks;
  st.pass2_ms += elapsed_ms(start);
  return vis;
}

}  // namespace

namespace {

/// Sub-light (i, j) of an n × n split of a rectangular light [Assarsson 2003 IV §5.2].
Light sub_light(const Light& light, int n, int i, int j) {
  Light sub = light;
  sub.edge_u = light.edge_u / static_cast<float>(n);
  sub.edge_v = light.edge_v / static_cast<float>(n);
  const Vec3 corner = light.center - 0.5f * (light.edge_u + light.edge_v);
  sub.center = corner + (static_cast<float>(i) + 0.5f) * sub.edge_u +
               (static_cast<float>(j) + 0.5f) * sub.edge_v;
  return sub;
}

/// The emission texture of sub-light (i, j) of an n × n split, at the texture's own resolution:
/// sub-texel (sx, sy) covers parent texel units [(i·w + sx)/n, (i·w + sx + 1)/n), which lies in
/// the single parent texel ⌊(i·w + sx)/n⌋ (likewise in y), so the nearest-texel emission of the
/// sub-square is reproduced exactly whatever n and the texture size.
Texture sub_texture(const Texture& t, int n, int i, int j) {
  if (n == 1 || t.width <= 0 || t.height <= 0 || t.texels.empty()) return t;
  Texture sub = t;
  for (int sy = 0; sy < t.height; ++sy) {
    const int ty = (j * t.height + sy) / n;
    for (int sx = 0; sx < t.width; ++sx) {
      const int tx = (i * t.width + sx) / n;
      for (int c = 0; c < t.channels; ++c)
        sub.texels[(static_cast<size_t>(sy) * t.width + sx) * t.channels + c] =
            t.channel(tx, ty, c);
    }
  }
  return sub;
}

/// A textured rectangular light: RGB visibility from the emission-weighted coverage,
/// exact per pixel (coverage = analytic) or from the RGB coverage table (coverage = texture), per
/// sub-light of the split, each with its own part of the texture. The sub-lights' per-channel
/// visible fractions are averaged with their emitted power as weights.
Image<float> textured_visibility(const ShadowContext& ctx, const FrameShared& shared,
                                 const WedgeOptions& options, int n, WedgeStats& st,
                                 Image<Vec3>* lit_rgb) {
  const Light& light = ctx.light;
  const Texture& texture = emission_texture(ctx.scene, light, "wedges");
  const GBuffer& g = ctx.gbuffer;
  Image<DVec3> seen(g.width, g.height, DVec3(0.0));  // Σ_k total_k ⊙ rgb_k
  DVec3 total(0.0);                                  // Σ_k total_k
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const LightEmission emission(sub_texture(texture, n, i, j), light.radiance);
      std::unique_ptr<CoverageTextureRGB> table;
      if (options.texture)
        table = std::make_unique<CoverageTextureRGB>(options.texture_n, emission);
      Image<Vec3> part_rgb(g.width, g.height, Vec3(1.0f));
      visibility_for_light(ctx, n == 1 ? light : sub_light(light, n, i, j), shared, options, st,
                           RgbLight{&emission, table.get(), &part_rgb});
      for (size_t k = 0; k < seen.size(); ++k) seen[k] += emission.total * DVec3(part_rgb[k]);
      total += emission.total;
    }
  }
  Image<float> vis(g.width, g.height, 1.0f);
  Image<Vec3> rgb(g.width, g.height, Vec3(1.0f));
  for (size_t k = 0; k < vis.size(); ++k) {
    DVec3 occluded(0.0);
    for (int c = 0; c < 3; ++c) occluded[c] = total[c] > 0.0 ? 1.0 - seen[k][c] / total[c] : 0.0;
    vis[k] = rgb_visibility(occluded, total, rgb[k]);
  }
  if (lit_rgb) *lit_rgb = std::move(rgb);
  return vis;
}

}  // namespace

Image<float> wedge_visibility(const ShadowContext& ctx, const WedgeOptions& options_in,
                              WedgeStats* stats_out, Image<Vec3>* lit_rgb,
                              const wedge_pass::CasterMeshes* prepared) {
  WedgeStats st;
  WedgeOptions options = options_in;
  const auto start = std::chrono::steady_clock::now();
  FrameShared shared{pixel_setup(ctx), prepared ? *prepared : caster_meshes(ctx.scene)};
  // Forest 2008 Algorithm 12 lines 5–6: perforated triangles leave the wedges for the STSV pass.
  stsv::Perforated perforated;
  if (options.alpha_stsv) perforated = stsv::take_perforated(ctx.scene, shared.casters);
  st.silhouettes_ms += elapsed_ms(start);  // the adjacency silhouettes need (and the pixel setup)
  const Light& light = ctx.light;
  // Light splitting [Assarsson 2003 IV §5.2]: rectangles only (a sub-square of a disk is not a
  // disk).
  const int n = light.shape == LightShape::rect ? std::max(1, options.split) : 1;
  st.sub_lights = static_cast<size_t>(n) * n;
  Image<float> vis;
  if (light.shape == LightShape::rect && light.is_textured()) {
    vis = textured_visibility(ctx, shared, options, n, st, lit_rgb);
  } else {
    if (options.texture && !options.table)
      options.table = std::make_shared<const CoverageTexture>(options.texture_n);
    vis = Image<float>(ctx.gbuffer.width, ctx.gbuffer.height, 0.0f);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const Image<float> part = visibility_for_light(
            ctx, n == 1 ? light : sub_light(light, n, i, j), shared, options, st);
        for (size_t k = 0; k < vis.size(); ++k) vis[k] += part[k] / static_cast<float>(n * n);
      }
    }
  }
  if (options.alpha_stsv)  // §5.2.1: the STSV V_coef added to the wedges' (lines 13–14)
    st.stsv = stsv::subtract_stsv_occlusion(ctx, shared.setup, std::move(perforated), vis,
                                            lit_rgb && !lit_rgb->empty() ? lit_rgb : nullptr);
  if (stats_out) *stats_out = st;
  return vis;
}

namespace {

class Wedges final : public ShadowMethod {
 public:
  explicit Wedges(WedgeOptions options) : options_(std::move(options)) {
    if (options_.texture && !options_.table)
      options_.table = std::make_shared<const CoverageTexture>(options_.texture_n);
  }

  /// The casters' adjacency (edges, re-oriented and de-duplicated meshes) is scene-static.
  void prepare(const Scene& scene) override {
    const auto start = std::chrono::steady_clock::now();
    casters_ = std::make_unique<const CasterMeshes>(caster_meshes(scene));
    unreported_prepare_ms_ = elapsed_ms(start);
  }

  Visibility compute(const ShadowContext& ctx) override {
    WedgeStats st;
    Visibility v;
    Image<Vec3> rgb;
    v.lit = wedge_visibility(ctx, options_, &st, &rgb, casters_.get());
    // The adjacency's time, once, in the stage that built it when it was built per light.
    st.silhouettes_ms += std::exchange(unreported_prepare_ms_, 0.0);
    if (!rgb.empty()) v.lit_rgb = std::move(rgb);
    report_wedge_stats(st, "pass2", v);
    v.counters["sub_lights"] = static_cast<double>(st.sub_lights);
    return v;
  }

 private:
  WedgeOptions options_;
  std::unique_ptr<const CasterMeshes> casters_;
  double unreported_prepare_ms_ = 0.0;
};

}  // namespace

void register_wedges(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "wedges";
  info.summary =
      "soft shadow volumes: hard count from the light centre plus analytic penumbra-wedge "
      "coverage per silhouette edge (rectangle, disk, sphere lights; textured rectangles in RGB); "
      "perforated triangles through soft textured shadow volumes, their per-sample V_coef added "
      "(alpha=stsv)";
  info.reference = "[Assarsson 2003 III §3, IV §4–5; Forest 2008 §3.1, App. 3.B, §5.2.1]";
  info.sample_exact = false;
  info.options = {
      wedge_construction_option(),
      stsv::alpha_option(),
      {"split",
       OptionType::integer,
       "1",
       "split a rectangular light into split x split sub-lights (Assarsson 2003 IV 5.2); ignored "
       "for round "
       "lights",
       {},
       1,
       16},
      {"overlap",
       OptionType::boolean,
       "false",
       "overlap approximation (Assarsson 2003 IV 5.1, eq. 1): per silhouette loop (light-facing "
       "patch) "
       "coverage, combined as max + 1/2 min",
       {},
       0,
       1},
      {"coverage",
       OptionType::choice,
       "analytic",
       "edge coverage on a rectangular light: analytic sector minus triangle, or the 4D coverage "
       "texture of Assarsson 2003 III 3.3; a textured rectangular light gets RGB visibility from "
       "the "
       "emission-weighted coverage (exact per texel, or the RGB coverage texture)",
       {"analytic", "texture"}},
      {"texture_n",
       OptionType::integer,
       "32",
       "coverage texture: n x n endpoint positions per endpoint (n^4 entries)",
       {},
       2,
       96},
      {"lookup",
       OptionType::choice,
       "bilinear",
       "coverage texture filtering: nearest first endpoint and bilinear second (bilinear), or "
       "bilinear in both (quadrilinear), Assarsson 2003 III 3.3",
       {"bilinear", "quadrilinear"}},
  };
  info.create = [](const MethodOptions& o) { return make_wedges(wedge_options_of(o)); };
  registry.add(std::move(info));
}

WedgeOptions wedge_options_of(const MethodOptions& o) {
  WedgeOptions w;
  w.construction = wedge_construction_of(o);
  w.split = o.get_int("split");
  w.alpha_stsv = stsv::uses_stsv(o);
  w.overlap = o.get_bool("overlap");
  w.texture = o.get_choice("coverage") == "texture";
  w.texture_n = o.get_int("texture_n");
  w.lookup = o.get_choice("lookup") == "quadrilinear" ? CoverageTexture::Lookup::quadrilinear
                                                      : CoverageTexture::Lookup::bilinear;
  return w;
}

std::unique_ptr<ShadowMethod> make_wedges(WedgeOptions options) {
  return std::make_unique<Wedges>(std::move(options));
}

OptionSpec wedge_construction_option() {
  return {"construction",
          OptionType::choice,
          "paper",
          "penumbra-wedge construction: paper (the farther vertex moved toward the light centre; "
          "Assarsson 2003 III 3.1, and Assarsson 2003 IV 4.1's tighter wedge for rectangles) or "
          "hull (the tightest "
          "polyhedral volume of the real edge); both conservative, docs/methods/wedges.md",
          {"paper", "hull"}};
}

WedgeConstruction wedge_construction_of(const MethodOptions& o) {
  return o.get_choice("construction") == "hull" ? WedgeConstruction::hull
                                                : WedgeConstruction::paper;
}

void report_wedge_stats(const WedgeStats& st, const char* pass2_stage, Visibility& v) {
  v.times.add("silhouettes", st.silhouettes_ms);
  v.times.add("pass1", st.pass1_ms);
  v.times.add("wedges", st.wedges_ms);
  v.times.add(pass2_stage, st.pass2_ms);
  v.counters["silhouette_edges"] = static_cast<double>(st.silhouette_edges);
  v.counters["wedges"] = static_cast<double>(st.wedges);
  if (!st.pass2_on_device) {
    v.counters["pixel_tests"] = static_cast<double>(st.pixel_tests);
    v.counters["pixels_inside_wedges"] = static_cast<double>(st.pixels_inside);
    v.counters["pixels_covered"] = static_cast<double>(st.pixels_covered);
  }
  v.counters["light_plane_fallbacks"] = static_cast<double>(st.plane_fallbacks);
  v.counters["wedge_construction_fallbacks"] = static_cast<double>(st.wedge_fallbacks);
  stsv::report(st.stsv, v);
}

}  // namespace penumbra
