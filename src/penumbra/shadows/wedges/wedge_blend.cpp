#include "penumbra/shadows/wedges/wedge_blend.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/coverage.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "penumbra/shadows/wedges/stsv_mask.hpp"

namespace penumbra {

namespace {

using namespace wedge_pass;

constexpr int kParts = 4;  // Forest 2008 §3.2.1, §3.3.3: four light parts split at the centre

double cross2(const DVec2& a, const DVec2& b) {
  return a.x * b.y - a.y * b.x;
}

/// A rectangle in part-local coordinates: s = |u − ½|, t = |v − ½| ∈ [0, ½] (the light centre at
/// the origin; every part treated "by symmetry" as the upper-right one, Forest 2008 §3.3.3).
struct Rect {
  double s0 = kInfinity, t0 = kInfinity, s1 = -kInfinity, t1 = -kInfinity;
  bool empty() const { return !(s1 > s0 && t1 > t0); }
  double area() const { return empty() ? 0.0 : (s1 - s0) * (t1 - t0); }
  void add(double s, double t) {
    s0 = std::min(s0, s);
    s1 = std::max(s1, s);
    t0 = std::min(t0, t);
    t1 = std::max(t1, t);
  }
  void add(const Rect& r) {
    if (r.empty()) return;
    add(r.s0, r.t0);
    add(r.s1, r.t1);
  }
  static Rect full() { return Rect{0.0, 0.0, 0.5, 0.5}; }
  static Rect intersection(const Rect& a, const Rect& b) {
    return Rect{std::max(a.s0, b.s0), std::max(a.t0, b.t0), std::min(a.s1, b.s1),
                std::min(a.t1, b.t1)};
  }
};

/// One light part of a V-buffer pixel [Forest 2008 Algorithm 6]: occluded fraction of the part's
/// light (per channel: its emitted power; the channels are equal for an untextured light) and
/// rectangle.
struct VPart {
  DVec3 occ{0.0};
  Rect rect;
};

/// One light part of an SV-buffer pixel [Forest 2008 §3.3.3: occ, brect, outer-edge maxima], plus
/// what the inner edges need to shrink the rectangle (their maxima and the angle they span).
struct SvPart {
  DVec3 occ{0.0};
  Rect rect;
  double outer_s = 0.0, outer_t = 0.0;
  double inner_s = 0.0, inner_t = 0.0, inner_angle = 0.0;
};

/// uv box of part q: bit 0 the u half, bit 1 the v half.
DVec2 part_lo(int q) {
  return DVec2(q & 1 ? 0.5 : 0.0, q & 2 ? 0.5 : 0.0);
}

/// Liang–Barsky clip of the uv segment a→b to part q's box; false if nothing (or a point) remains.
bool clip_to_part(int q, DVec2& a, DVec2& b) {
  const DVec2 lo = part_lo(q), hi = lo + DVec2(0.5);
  double t0 = 0.0, t1 = 1.0;
  const DVec2 d = b - a;
  const double p[4] = {-d.x, d.x, -d.y, d.y};
  const double r[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (r[k] < 0.0) return false;
      continue;
    }
    const double t = r[k] / p[k];
    if (p[k] < 0.0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
  }
  if (!(t0 < t1)) return false;
  // Clamped: rounding must not put an end a hair outside the part (the sector's rays start at its
  // corner c).
  const DVec2 na = glm::clamp(a + t0 * d, lo, hi), nb = glm::clamp(a + t1 * d, lo, hi);
  a = na;
  b = nb;
  return true;
}

/// The sector from the light centre c spanned by a and b (both in part q) within that part
/// [Forest 2008 §3.2.1]: its area minus the triangle (c, a, b), and the part-local rectangle that
/// bounds the region between a→b and the part's boundary [Forest fig. 3.6] — a, b and the
/// sector's outline in the part (c excluded).
struct PartSector {
  double area = 0.0;
  Rect rect;
};

bool part_sector(int q, const DVec2& a, const DVec2& b, PartSector& out) {
  const BoxSector sector = box_sector(part_lo(q), part_lo(q) + DVec2(0.5), a, b);
  if (sector.tri2 == 0.0) return false;
  out.area = sector.minus_triangle();
  out.rect = Rect{};
  const auto add_uv = [&](const DVec2& p) {
    out.rect.add(std::abs(p.x - 0.5), std::abs(p.y - 0.5));
  };
  add_uv(a);
  add_uv(b);
  for (int i = 0; i < sector.n; ++i) add_uv(sector.outline[i]);
  return true;
}

/// How the blend measures light. Eq. 3.1's A (occluded), B (rectangle) and β (intersection)
/// are areas for a uniform light; for a textured rectangle each channel measures emitted power
/// instead (fraction of the channel's total), which reduces to the areas for a uniform texture.
/// Every share is a fraction of the whole light.
class LightMeasure {
 public:
  LightMeasure(const LightEmission* emission, bool round)
      : emission_(emission), light_uv_area_(round ? kPi * 0.25 : 1.0) {
    for (int q = 0; q < kParts; ++q)
      part_[q] = emission_ ? emission_in_box(*emission_, part_lo(q), part_lo(q) + DVec2(0.5))
                           : DVec3(1.0 / kParts);
  }
  /// Share of the light in part q.
  const DVec3& part(int q) const { return part_[q]; }
  /// Share of the light in the part-local rectangle r of part q.
  DVec3 rect(int q, const Rect& r) const {
    if (r.empty()) return DVec3(0.0);
    if (!emission_) return DVec3(r.area() / light_uv_area_);
    const double u0 = q & 1 ? 0.5 + r.s0 : 0.5 - r.s1, u1 = q & 1 ? 0.5 + r.s1 : 0.5 - r.s0;
    const double v0 = q & 2 ? 0.5 + r.t0 : 0.5 - r.t1, v1 = q & 2 ? 0.5 + r.t1 : 0.5 - r.t0;
    return emission_in_box(*emission_, DVec2(u0, v0), DVec2(u1, v1));
  }
  /// Share of the light an edge clipped to a part (a, b; its uv sector-minus-triangle `uv_area`)
  /// adds (outer) or removes (inner).
  DVec3 edge(const PixelLight& pl, const Wedge& w, const DVec2& a, const DVec2& b,
             double uv_area) const {
    if (!emission_) return DVec3(pl.occlusion(w, uv_area));
    const DVec3 f = weighted_sector_minus_triangle(*emission_, a, b);
    return DVec3(pl.occlusion(w, f.x), pl.occlusion(w, f.y), pl.occlusion(w, f.z));
  }

 private:
  const LightEmission* emission_;
  double light_uv_area_;
  std::array<DVec3, kParts> part_{};
};

bool any_positive(const DVec3& v) {
  return v.x > 0.0 || v.y > 0.0 || v.z > 0.0;
}

/// Algorithm 6 for part q: blends the SV part into the V part with the effective overlapped area
/// heuristic (eq. 3.1), per channel.
void blend_part(const SvPart& s, VPart& v, int q, const LightMeasure& m, WedgeBlendStats& st) {
  if (!any_positive(s.occ)) return;
  if (!any_positive(v.occ)) {
    v.occ = s.occ;
    v.rect = s.rect;
    return;
  }
  ++st.blends;
  DVec3 blended = s.occ + v.occ;  // line 7
  const Rect inter = Rect::intersection(s.rect, v.rect);
  if (inter.area() > 0.0) {  // lines 8–11
    ++st.overlaps;
    const DVec3 bs = m.rect(q, s.rect), bv = m.rect(q, v.rect), beta = m.rect(q, inter);
    const DVec3& w = m.part(q);
    for (int c = 0; c < 3; ++c) {
      if (!(w[c] > 0.0)) continue;  // the part emits nothing in this channel
      const double ratio_s = bs[c] > 0.0 ? std::min(1.0, s.occ[c] * w[c] / bs[c]) : 1.0,
                   ratio_v = bv[c] > 0.0 ? std::min(1.0, v.occ[c] * w[c] / bv[c]) : 1.0;
      blended[c] -= ratio_v * ratio_s * beta[c] / w[c];  // eq. 3.1, as a share of the part
    }
  }
  v.occ = glm::clamp(blended, DVec3(0.0), DVec3(1.0));  // line 13
  v.rect.add(s.rect);                                   // line 14: merge_brect
}

/// The per-pixel blend by `pass2`: V (and a textured light's per-channel visible fractions) from
/// the occlusion per channel it returns, as the CPU pass turns its V-buffer into V.
Image<float> device_pass2(const ShadowContext& ctx, const WedgeBlendPass2& pass2,
                          const BinnedWedges& bw, const GroupCounts& gcount,
                          const LightEmission* emission, const LightMeasure& measure,
                          Image<Vec3>& rgb) {
  WedgeBlendPass2Input in{bw, gcount, emission, {}};
  for (int q = 0; q < kParts; ++q) in.parts[q] = measure.part(q);
  const Image<DVec3> occ = pass2(ctx, in);
  Image<float> vis(ctx.gbuffer.width, ctx.gbuffer.height, 1.0f);
  for (size_t i = 0; i < vis.size(); ++i) {
    if (ctx.receivers[i] != kActive) continue;
    vis[i] = emission ? rgb_visibility(occ[i], emission->total, rgb[i])
                      : static_cast<float>(1.0 - std::clamp(occ[i].x, 0.0, 1.0));
  }
  return vis;
}

}  // namespace

Image<float> wedge_blend_visibility(const ShadowContext& ctx, WedgeBlendStats* stats_out,
                                    WedgeConstruction construction, Image<Vec3>* lit_rgb,
                                    bool alpha_stsv, const wedge_pass::CasterMeshes* prepared,
                                    const WedgeBlendPass2& pass2) {
  WedgeBlendStats st;
  WedgeStats& ws = st.wedges;
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  const PixelSetup setup = pixel_setup(ctx);
  const Vec3 centre = hard_shadow_point(light);
  // A textured rectangular light: every share is emitted power per channel (LightMeasure).
  std::unique_ptr<LightEmission> emission;
  if (light.shape == LightShape::rect && light.is_textured())
    emission = std::make_unique<LightEmission>(emission_texture(ctx.scene, light, "wedge_blend"),
                                               light.radiance);
  const LightMeasure measure(emission.get(),
                             light.shape == LightShape::disk || light.shape == LightShape::sphere);
  Image<Vec3> rgb_img;
  if (emission) rgb_img = Image<Vec3>(g.width, g.height, Vec3(1.0f));

  // Silhouette loops from the light centre, grouped per light-facing patch (Algorithm 4
  // line 1, wedges/pass.hpp).
  auto start = std::chrono::steady_clock::now();
  CasterMeshes caster_set = prepared ? *prepared : caster_meshes(ctx.scene);
  // Forest 2008 Algorithm 12 lines 5–6: perforated triangles leave the wedges for the STSV pass.
  stsv::Perforated perforated;
  if (alpha_stsv) perforated = stsv::take_perforated(ctx.scene, caster_set);
  const Casters casters = make_casters(caster_set, centre);
  const std::vector<WedgeEdge> sil = silhouette_edges(casters, centre);
  st.groups = casters.meshes.size();
  ws.silhouette_edges = sil.size();
  ws.sub_lights = 1;
  ws.silhouettes_ms = elapsed_ms(start);

  // Algorithm 4 line 4: each group's hard shadow from its own shadow volume.
  start = std::chrono::steady_clock::now();
  const GroupCounts gcount = group_counts(ctx, casters, centre, &setup.volume);
  ws.pass1_ms = elapsed_ms(start);

  const WedgeLight wl = wedge_light(light);
  start = std::chrono::steady_clock::now();
  BinnedWedges bw;
  if (!wl.hull.empty() && !sil.empty() && setup.any_active)
    bw = build_and_bin(ctx, setup, sil, wl, construction);
  else  // point light: no wedges, the hard counts alone (one empty tile grid)
    bw = build_and_bin(ctx, setup, {}, wl, construction);
  ws.wedges = bw.wedges.size();
  ws.wedge_fallbacks = bw.degenerate;
  ws.wedges_ms = elapsed_ms(start);

  // Algorithm 4 lines 2–7 per pixel: SV-buffer of each group (Algorithm 5), blended into the
  // V-buffer (Algorithm 6). Everything is per pixel, so the buffers are per-pixel locals.
  start = std::chrono::steady_clock::now();
  PassCounters pc;
  std::vector<WedgeBlendStats> row_stats(bw.tiles_y);
  Image<float> vis =
      pass2 ? device_pass2(ctx, pass2, bw, gcount, emission.get(), measure, rgb_img)
            : run_pass2(
                  ctx, light, bw, pc,
                  [&](size_t i, const PixelLight* pl, const std::vector<uint32_t>& bin,
                      PassCounters& c) {
                    WedgeBlendStats& rs = row_stats[(i / g.width) / kTile];
                    std::array<VPart, kParts> vbuf{};
                    for_each_group(
                        gcount, i, pl, bin, &bw, c,
                        [&](uint32_t, double count, const std::vector<CoveredEdge>& edges) {
                          // SV-buffer initialised by the group's hard count (Algorithm 4 line 4).
                          std::array<SvPart, kParts> sv{};
                          for (SvPart& p : sv) {
                            p.occ = DVec3(count);
                            if (count > 0.0) p.rect = Rect::full();
                          }
                          // Algorithm 5, outer half-wedges first (§3.3.3), then inner ones.
                          for (int pass = 0; pass < 2 && pl; ++pass) {
                            for (const CoveredEdge& e : edges) {
                              const Wedge& w = bw.wedges[e.wedge];
                              const bool outer = pl->occlusion(w, e.area) > 0.0;
                              if (outer != (pass == 0)) continue;
                              // The parts the segment's box reaches (most edges lie in one or two).
                              const bool u_half[2] = {std::min(e.a.x, e.b.x) <= 0.5,
                                                      std::max(e.a.x, e.b.x) >= 0.5};
                              const bool v_half[2] = {std::min(e.a.y, e.b.y) <= 0.5,
                                                      std::max(e.a.y, e.b.y) >= 0.5};
                              for (int q = 0; q < kParts; ++q) {
                                if (!u_half[q & 1] || !v_half[(q >> 1) & 1]) continue;
                                DVec2 a = e.a, b = e.b;
                                if (!clip_to_part(q, a, b)) continue;  // line 7
                                // The sector from the centre through a, b lies in part q: its part
                                // of the square gives both the square's sector-minus-triangle and
                                // the rectangle.
                                PartSector sector;
                                if (!part_sector(q, a, b, sector)) continue;
                                const double area =
                                    pl->round() ? disk_sector_minus_triangle(a, b) : sector.area;
                                if (area == 0.0) continue;
                                SvPart& p = sv[q];
                                const DVec3 share = measure.edge(*pl, w, a, b, area);  // line 8
                                const DVec3& part = measure.part(q);
                                for (int k = 0; k < 3; ++k)  // lines 11, 14
                                  if (part[k] > 0.0) p.occ[k] += share[k] / part[k];
                                const double as = std::abs(a.x - 0.5), at = std::abs(a.y - 0.5),
                                             bs = std::abs(b.x - 0.5), bt = std::abs(b.y - 0.5);
                                if (outer) {  // line 12: increase_brect; outer-edge maxima
                                  p.rect.add(sector.rect);
                                  p.outer_s = std::max({p.outer_s, as, bs});
                                  p.outer_t = std::max({p.outer_t, at, bt});
                                } else {  // line 15: decrease_brect (below)
                                  p.inner_s = std::max({p.inner_s, as, bs});
                                  p.inner_t = std::max({p.inner_t, at, bt});
                                  const DVec2 da = a - DVec2(0.5), db = b - DVec2(0.5);
                                  p.inner_angle +=
                                      std::abs(std::atan2(cross2(da, db), glm::dot(da, db)));
                                }
                              }
                            }
                          }
                          for (int q = 0; q < kParts; ++q) {
                            SvPart& p = sv[q];
                            // decrease_brect: inner edges spanning the whole part (90° seen from
                            // the centre) close the occluded region off on the centre's side; it
                            // reaches no farther than they do, nor than the occluding outer edges
                            // (the maxima of §3.3.3).
                            if (p.inner_angle >= 0.5 * kPi * (1.0 - 1e-9) && !p.rect.empty()) {
                              p.rect.s1 = std::max(
                                  p.rect.s0, std::min(p.rect.s1, std::max(p.inner_s, p.outer_s)));
                              p.rect.t1 = std::max(
                                  p.rect.t0, std::min(p.rect.t1, std::max(p.inner_t, p.outer_t)));
                            }
                            p.occ = glm::clamp(p.occ, DVec3(0.0), DVec3(1.0));
                            blend_part(p, vbuf[q], q, measure, rs);  // Algorithm 4 line 7
                          }
                        });
                    DVec3 occ(0.0);
                    for (int q = 0; q < kParts; ++q) occ += measure.part(q) * vbuf[q].occ;
                    if (emission) return rgb_visibility(occ, emission->total, rgb_img[i]);
                    return static_cast<float>(1.0 - std::clamp(occ.x, 0.0, 1.0));
                  });
  for (const WedgeBlendStats& r : row_stats) {
    st.blends += r.blends;
    st.overlaps += r.overlaps;
  }
  ws.pass2_on_device = static_cast<bool>(pass2);  // which counts none of these
  ws.pixel_tests = pc.tests;
  ws.pixels_inside = pc.inside;
  ws.pixels_covered = pc.covered;
  ws.plane_fallbacks = pc.fallbacks;
  ws.pass2_ms = elapsed_ms(start);
  if (alpha_stsv)  // §5.2.1: the STSV V_coef added to the blended one (lines 13–14)
    ws.stsv = stsv::subtract_stsv_occlusion(ctx, setup, std::move(perforated), vis,
                                            emission ? &rgb_img : nullptr);
  if (stats_out) *stats_out = st;
  if (lit_rgb && emission) *lit_rgb = std::move(rgb_img);
  return vis;
}

namespace {

class WedgeBlend final : public ShadowMethod {
 public:
  WedgeBlend(WedgeConstruction construction, bool alpha_stsv, WedgeBlendPass2 pass2 = {})
      : construction_(construction), alpha_stsv_(alpha_stsv), pass2_(std::move(pass2)) {}

  /// The casters' adjacency (edges, re-oriented and de-duplicated meshes) is scene-static.
  void prepare(const Scene& scene) override {
    const auto start = std::chrono::steady_clock::now();
    casters_ = std::make_unique<const CasterMeshes>(caster_meshes(scene));
    unreported_prepare_ms_ = elapsed_ms(start);
  }

  Visibility compute(const ShadowContext& ctx) override {
    WedgeBlendStats st;
    Visibility v;
    Image<Vec3> rgb;
    v.lit =
        wedge_blend_visibility(ctx, &st, construction_, &rgb, alpha_stsv_, casters_.get(), pass2_);
    // The adjacency's time, once, in the stage that built it when it was built per light.
    st.wedges.silhouettes_ms += std::exchange(unreported_prepare_ms_, 0.0);
    if (!rgb.empty()) v.lit_rgb = std::move(rgb);
    report_wedge_stats(st.wedges, "pass2_blend", v);
    v.counters["groups"] = static_cast<double>(st.groups);
    if (!st.wedges.pass2_on_device) {
      v.counters["part_blends"] = static_cast<double>(st.blends);
      v.counters["part_overlaps"] = static_cast<double>(st.overlaps);
    }
    return v;
  }

 private:
  WedgeConstruction construction_;
  bool alpha_stsv_;
  WedgeBlendPass2 pass2_;
  std::unique_ptr<const CasterMeshes> casters_;
  double unreported_prepare_ms_ = 0.0;
};

}  // namespace

std::unique_ptr<ShadowMethod> make_wedge_blend(const MethodOptions& options,
                                               WedgeBlendPass2 pass2) {
  return std::make_unique<WedgeBlend>(wedge_construction_of(options), stsv::uses_stsv(options),
                                      std::move(pass2));
}

void register_wedge_blend(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "wedge_blend";
  info.summary =
      "penumbra-wedge blending: per caster group an SV-buffer of four light parts (occlusion, "
      "bounding rectangle), blended with the effective overlapped area heuristic; perforated "
      "triangles through soft textured shadow volumes (alpha=stsv)";
  info.reference = "[Forest 2008 §3.2, Algorithms 4-6, eq. 3.1, §3.3.3-3.3.4, §5.2.1]";
  info.sample_exact = false;
  info.options = {wedge_construction_option(), stsv::alpha_option()};
  info.create = [](const MethodOptions& o) {
    return std::make_unique<WedgeBlend>(wedge_construction_of(o), stsv::uses_stsv(o));
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
