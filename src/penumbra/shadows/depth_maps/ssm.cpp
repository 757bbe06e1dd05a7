// `ssm`: Soft Shadow Maps [Atty 2006 §3], one-pass and two-pass (§3.5). See depth_maps/ssm.hpp and
// docs/methods/ssm.md.
//
// Stages of compute():
//  1. occluder/receiver split [Atty 2006 §3.1]: a mesh with casts_shadows only is an occluder, with
//     receives_shadows only a receiver; meshes with both flags (the default) are occluders, except
//     — when no mesh is receiver-only — the largest one (bounding-box diagonal: the ground), which
//     receives only. Occluder pixels get no shadow (V = 1): the method has no self-shadowing.
//  2. windows in the light's tangent space (x/z, y/z from the light centre, axes along the light's
//     edges): the occluder window around the occluders, with the light's aspect ratio so that its
//     texels (resolution²) and hence the micro-patches have the light's aspect [Atty 2006 §3.2];
//     the soft-shadow-map window = the receivers seen by the camera ∩ the occluders' penumbra.
//  3. occluder map(s): nearest front faces; two-pass adds the furthest back faces [Atty 2006 §3.5];
//     receiver map (nearest receiver depth) on the soft-shadow-map grid.
//  4. per occluder texel: micro-patch, pyramid apex and extent [Atty 2006 §3.3], occlusion of every
//     soft-shadow-map texel in the extent from its receiver depth [Atty 2006 §3.4], summed in
//     float32 (option fp16: every blend rounded to binary16, appendix A).
//  5. two-pass: per-texel max of the two soft shadow maps; projection onto the G-buffer pixels
//     from the light centre (bilinear over texels holding a receiver).
#include "penumbra/shadows/depth_maps/ssm.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <tuple>
#include <utility>

#include "penumbra/core/parallel.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

using ssm::DVec3;
using ssm::LightRect;
using ssm::Window;

constexpr double kMaxTan = 11.430052302761343;  // tan 85°: the widest window
constexpr int kBand = 8;
constexpr int kMinResolution = 4;  // the smallest occluder map the budget halves down to

void assign_roles(const Scene& s, std::vector<bool>& occ, std::vector<bool>& rec) {
  const size_t n = s.meshes.size();
  occ.assign(n, false);
  rec.assign(n, false);
  bool receiver_only = false;
  for (const Mesh& m : s.meshes) receiver_only |= (!m.casts_shadows && m.receives_shadows);
  size_t ground = n;
  float best = -1.0f;
  if (!receiver_only)
    for (size_t i = 0; i < n; ++i)
      if (s.meshes[i].casts_shadows && s.meshes[i].receives_shadows &&
          s.meshes[i].bounds().diagonal() > best) {
        best = s.meshes[i].bounds().diagonal();
        ground = i;
      }
  for (size_t i = 0; i < n; ++i) {
    const Mesh& m = s.meshes[i];
    if (m.casts_shadows && m.receives_shadows) {
      (i == ground ? rec : occ)[i] = true;
    } else {
      occ[i] = m.casts_shadows;
      rec[i] = m.receives_shadows;
    }
  }
}

/// Tangent bounding box accumulator.
struct TanBox {
  double x0 = kInfinity, x1 = -kInfinity, y0 = kInfinity, y1 = -kInfinity;
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  /// Adds a light-space point; one at or behind the near depth opens the box to the cap.
  void add_point(const DVec3& l, double near) {
    if (l.z <= near) {
      add(-kMaxTan, -kMaxTan);
      add(kMaxTan, kMaxTan);
    } else {
      add(std::clamp(l.x / l.z, -kMaxTan, kMaxTan), std::clamp(l.y / l.z, -kMaxTan, kMaxTan));
    }
  }
  bool empty() const { return !(x1 >= x0) || !(y1 >= y0); }
};

using ssm::Patch;

/// Receiver-map depths within this fraction of a point's own depth are the same receiver.
constexpr double kSameReceiverDepth = 0.05;

/// Stages 1–2: the roles, the light's frame and near depth, the receivers' tangent box and
/// farthest depth, and the box of the occluders within reach of a receiver.
struct Fit {
  std::vector<bool> occ, rec;
  LightRect light;
  double near = 0.0;
  TanBox rbox, obox;
  double zr_max = 0.0;
};

/// The light's frame, with lengths relative to what the camera sees from this light (the
/// receivers' box and its distance), not to the whole scene: one mesh far away must not make the
/// near plane or a point light's square swallow the visible shadows.
void fit_light(const ShadowContext& ctx, Fit& fit) {
  const GBuffer& g = ctx.gbuffer;
  Bounds3 active_box;
  for (size_t i = 0; i < g.pixel_count(); ++i)
    if (ctx.receivers[i] == kActive) active_box.extend(g.shadow_origin(i));
  const DVec3 toward =
      active_box.empty() ? DVec3(ctx.light.center) - DVec3(0, 1, 0) : DVec3(active_box.center());
  const double local_scale = active_box.empty()
                                 ? std::max(1e-3f, ctx.scene.bounds().diagonal())
                                 : std::max({glm::length(toward - DVec3(ctx.light.center)),
                                             static_cast<double>(active_box.diagonal()), 1e-30});
  fit.near = 1e-6 * local_scale;
  fit.light = ssm::light_rect(ctx.light, toward, fit.near);
}

/// The receivers' tangent box and farthest depth; returns the count of active pixels on
/// occluders (which get no shadow).
double fit_receivers(const ShadowContext& ctx, Fit& fit) {
  const GBuffer& g = ctx.gbuffer;
  double occluder_pixels = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (ctx.receivers[i] != kActive) continue;
    if (!fit.rec[g.mesh_id[i]]) {
      ++occluder_pixels;
      continue;
    }
    const DVec3 l = fit.light.local(DVec3(g.shadow_origin(i)));
    if (l.z <= fit.near) continue;
    fit.rbox.add_point(l, fit.near);
    fit.zr_max = std::max(fit.zr_max, l.z);
  }
  return occluder_pixels;
}

/// Only occluders within reach of a receiver matter: a point at depth z_O shadows tangents
/// within L/2·(1/z_O − 1/z_R) < L/(2·z_O) of its own (§3.3), and on a triangle z_O is at least
/// its nearest vertex's (depth is linear). The occluder window is the union of each triangle's
/// tangent box cut to that reach, so far-away geometry does not spread its texels over empty
/// space.
void fit_occluders(const Scene& scene, Fit& fit) {
  const LightRect& light = fit.light;
  const TanBox& rbox = fit.rbox;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (!fit.occ[m]) continue;
    const Mesh& mesh = scene.meshes[m];
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      TanBox tri;
      double z_min = kInfinity;
      for (int k = 0; k < 3; ++k) {
        const DVec3 l = light.local(DVec3(mesh.vertex(t, k)));
        tri.add_point(l, fit.near);
        z_min = std::min(z_min, l.z);
      }
      if (z_min > fit.near) {
        const double mx = 0.5 * light.lu / z_min, my = 0.5 * light.lv / z_min;
        tri.x0 = std::max(tri.x0, rbox.x0 - mx);
        tri.x1 = std::min(tri.x1, rbox.x1 + mx);
        tri.y0 = std::max(tri.y0, rbox.y0 - my);
        tri.y1 = std::min(tri.y1, rbox.y1 + my);
      }
      if (tri.empty()) continue;
      fit.obox.add(tri.x0, tri.y0);
      fit.obox.add(tri.x1, tri.y1);
    }
  }
}

/// The occluder window around `obox` at `res`² texels: a 1e-6 relative margin, then widened to
/// the light's aspect ratio, so that its texels and hence the micro-patches have the light's
/// aspect [Atty 2006 §3.2].
Window occluder_window(const TanBox& obox, const LightRect& light, int res) {
  const double cx = 0.5 * (obox.x0 + obox.x1), cy = 0.5 * (obox.y0 + obox.y1);
  double wx = (obox.x1 - obox.x0) * (1.0 + 1e-6) + 1e-9;
  double wy = (obox.y1 - obox.y0) * (1.0 + 1e-6) + 1e-9;
  const double aspect = light.lu / light.lv;
  if (wx < wy * aspect)
    wx = wy * aspect;
  else
    wy = wx / aspect;
  return {cx - 0.5 * wx, cx + 0.5 * wx, cy - 0.5 * wy, cy + 0.5 * wy, res, res};
}

/// The soft-shadow-map window at `ssm_res`² texels: the receivers ∩ the occluder window grown by
/// the widest penumbra half-extent (§3.3 at the nearest occluder depth and the farthest receiver
/// depth).
Window ssm_window(const Window& ow, const TanBox& rbox, const LightRect& light, double zo_min,
                  double zr_max, int ssm_res) {
  Window sw;
  const double mx = 0.5 * ow.dx() + 0.5 * light.lu * (1.0 / zo_min - 1.0 / zr_max);
  const double my = 0.5 * ow.dy() + 0.5 * light.lv * (1.0 / zo_min - 1.0 / zr_max);
  sw.tx0 = std::max(rbox.x0, ow.tx0 - mx);
  sw.tx1 = std::min(rbox.x1, ow.tx1 + mx);
  sw.ty0 = std::max(rbox.y0, ow.ty0 - my);
  sw.ty1 = std::min(rbox.y1, ow.ty1 + my);
  // A half-texel margin so that bilinear lookups at the receivers' edge stay inside.
  const double ex = (sw.tx1 - sw.tx0) / ssm_res, ey = (sw.ty1 - sw.ty0) / ssm_res;
  sw.tx0 -= ex;
  sw.tx1 += ex;
  sw.ty0 -= ey;
  sw.ty1 += ey;
  sw.w = sw.h = ssm_res;
  return sw;
}

/// Stage 4 on the CPU: every patch's occlusion of the soft-shadow-map texels in its extent
/// [Atty 2006 §3.4], in occluder-map order (the blending order); `touched`: the texel updates.
Image<float> blend_patches(const std::vector<Patch>& patches, const Window& sw,
                           const Image<float>& rmap, const LightRect& light, bool fp16,
                           double& touched) {
  std::atomic<long long> updates{0};
  Image<float> acc(sw.w, sw.h, 0.0f);
  parallel_bands(sw.h, kBand, [&](int first, int last) {
    long long local = 0;
    for (const Patch& p : patches) {  // occluder-map order: the blending order
      const int j0 = std::max(p.j0, first), j1 = std::min(p.j1, last - 1);
      for (int j = j0; j <= j1; ++j) {
        const double ty = sw.centre_y(j);
        for (int i = p.i0; i <= p.i1; ++i) {
          const float zr = rmap(i, j);
          if (!(zr < kInfinity)) continue;
          ++local;
          const double o = ssm::patch_occlusion(p.px, p.py, p.hx, p.hy, p.zo, zr * sw.centre_x(i),
                                                zr * ty, zr, light.lu, light.lv);
          if (o <= 0.0) continue;
          float& a = acc(i, j);
          // fp16: the contribution is stored as binary16, the blend truncates (App. A).
          a = fp16 ? ssm::round_to_half(a + ssm::round_to_half(static_cast<float>(o)), true)
                   : a + static_cast<float>(o);
        }
      }
    }
    updates += local;
  });
  touched = static_cast<double>(updates.load());
  return acc;
}

/// The merged soft shadow map's occlusion at light-space point l (bilinear over the four texels
/// around it), or false where none of them holds a receiver. Texels whose receiver depth is this
/// point's are preferred: a texel holding a nearer receiver (an occluder that also receives)
/// carries that receiver's occlusion, not this point's, and mixing it in flips pixels along the
/// boundary at the mercy of sub-texel shifts. `hidden`: no texel at the point's own depth.
bool lookup_occlusion(const Window& sw, const Image<float>& rmap, const Image<float>& merged,
                      const DVec3& l, double& occlusion, bool& hidden) {
  const double u = sw.to_u(l.x / l.z) - 0.5, v = sw.to_v(l.y / l.z) - 0.5;
  const double fu = std::floor(u), fv = std::floor(v);
  if (!(fu >= -1.0 && fu < sw.w && fv >= -1.0 && fv < sw.h)) return false;
  const int i0 = static_cast<int>(fu), j0 = static_cast<int>(fv);
  double sum = 0.0, wsum = 0.0, same_sum = 0.0, same_wsum = 0.0;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const int ti = i0 + di, tj = j0 + dj;
      if (ti < 0 || tj < 0 || ti >= sw.w || tj >= sw.h) continue;
      const float zr = rmap(ti, tj);
      if (!(zr < kInfinity)) continue;
      const double w = (di ? u - fu : 1.0 - (u - fu)) * (dj ? v - fv : 1.0 - (v - fv));
      sum += w * merged(ti, tj);
      wsum += w;
      if (std::abs(zr - l.z) <= kSameReceiverDepth * l.z) {
        same_sum += w * merged(ti, tj);
        same_wsum += w;
      }
    }
  if (!(wsum > 0.0)) return false;
  if (same_wsum > 0.0) {
    sum = same_sum;
    wsum = same_wsum;
  }
  occlusion = sum / wsum;
  hidden = same_wsum == 0.0;
  return true;
}

/// Stage 5's projection of the merged soft shadow map onto the receiver pixels from the light
/// centre. Returns the receivers with no texel at their own depth, hidden from the light centre
/// by a nearer receiver: they read the nearer one's occlusion (the receiver map keeps one depth
/// per texel), counted, not corrected.
long long project_onto_pixels(const ShadowContext& ctx, const Fit& fit, const Window& sw,
                              const Image<float>& rmap, const Image<float>& merged,
                              Image<float>& lit) {
  const GBuffer& g = ctx.gbuffer;
  std::atomic<long long> hidden{0};
  parallel_rows(g.height, [&](int y) {
    long long local_hidden = 0;
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (ctx.receivers[i] != kActive || !fit.rec[g.mesh_id[i]]) continue;
      const DVec3 l = fit.light.local(DVec3(g.shadow_origin(i)));
      if (l.z <= fit.near) continue;
      double occlusion = 0.0;
      bool hidden_here = false;
      if (!lookup_occlusion(sw, rmap, merged, l, occlusion, hidden_here)) continue;
      local_hidden += hidden_here;
      lit[i] = static_cast<float>(1.0 - std::clamp(occlusion, 0.0, 1.0));
    }
    hidden += local_hidden;
  });
  return hidden.load();
}

class Ssm final : public ShadowMethod {
 public:
  Ssm(const MethodOptions& o, ssm::Blend blend)
      : blend_(std::move(blend)),
        res_(o.get_int("resolution")),
        ssm_res_(o.get_int("ssm_resolution")),
        two_pass_(o.get_bool("two_pass")),
        back_furthest_(o.get_choice("back_depth") == "furthest"),
        fp16_(o.get_bool("fp16")),
        merge_(o.get_bool("merge")),
        budget_(1e6 * o.get_int("budget")) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    const Fit fit = fit_windows(ctx, vis);
    if (fit.rbox.empty() || fit.obox.empty()) return vis;
    const Maps maps = maps_within_budget(ctx.scene, fit, vis);
    if (maps.patches[0].empty() && maps.patches[1].empty()) return vis;

    // 4. One soft shadow map per occluder map.
    std::vector<Image<float>> ssms;
    double touched_total = 0;
    for (size_t pass = 0; pass < (two_pass_ ? 2u : 1u); ++pass) {
      ScopedStage stage(vis.times, pass == 0 ? "ssm_front" : "ssm_back");
      double touched = 0.0;
      ssms.push_back(
          blend_ && !fp16_
              ? blend_(maps.patches[pass], maps.sw, maps.rmap, fit.light, touched)
              : blend_patches(maps.patches[pass], maps.sw, maps.rmap, fit.light, fp16_, touched));
      touched_total += touched;
    }
    vis.counters["penumbra_texels"] = touched_total;

    // 5. Merge (max, §3.5) and project onto the G-buffer.
    long long hidden = 0;
    {
      ScopedStage stage(vis.times, "project");
      Image<float> merged = std::move(ssms[0]);
      for (size_t k = 1; k < ssms.size(); ++k)
        for (size_t t = 0; t < merged.size(); ++t)
          merged.pixels()[t] = std::max(merged.pixels()[t], ssms[k].pixels()[t]);
      hidden = project_onto_pixels(ctx, fit, maps.sw, maps.rmap, merged, vis.lit);
    }
    vis.counters["hidden_receiver_pixels"] = static_cast<double>(hidden);
    vis.counters["ssm_tan_width"] = maps.sw.tx1 - maps.sw.tx0;
    return vis;
  }

 private:
  struct Maps {
    Window sw;
    Image<float> rmap;
    std::vector<Patch> patches[2];  // front, back (two-pass)
    double occluder_texels = 0, work = 0;
  };

  /// Stages 1–2: roles, the light's frame, the receiver box and the occluder window's box.
  static Fit fit_windows(const ShadowContext& ctx, Visibility& vis) {
    ScopedStage stage(vis.times, "fit");
    Fit fit;
    assign_roles(ctx.scene, fit.occ, fit.rec);
    fit_light(ctx, fit);
    vis.counters["light_lu"] = fit.light.lu;
    vis.counters["light_lv"] = fit.light.lv;
    vis.counters["occluder_pixels"] = fit_receivers(ctx, fit);
    fit_occluders(ctx.scene, fit);
    return fit;
  }

  /// Stage 3 at the largest occluder-map resolution within the budget: halved while the blending
  /// work (occluder texels × extent texels, §5.1) exceeds it — the paper's own remedy: "if we
  /// have a large penumbra zone, we can use a lower resolution".
  Maps maps_within_budget(const Scene& scene, const Fit& fit, Visibility& vis) const {
    Maps maps;
    int res = res_, halvings = 0;
    for (;;) {
      maps = build_maps(scene, fit, res, vis.times);
      if (maps.work <= budget_ || res <= kMinResolution) break;
      res = std::max(kMinResolution, res / 2);
      ++halvings;
    }
    vis.counters["occluder_texels"] = maps.occluder_texels;
    vis.counters["occluder_resolution"] = res;
    vis.counters["budget_halvings"] = halvings;
    vis.counters["patches"] = static_cast<double>(maps.patches[0].size() + maps.patches[1].size());
    vis.counters["update_bound"] = maps.work;
    return maps;
  }

  /// Stage 3 at occluder-map resolution `res`: the occluder window, the occluder maps, the
  /// soft-shadow-map window, the receiver map and the micro-patches.
  Maps build_maps(const Scene& scene, const Fit& fit, int res, StageTimes& times) const {
    Maps out;
    ScopedStage occluder_stage(times, "occluder_map");
    const Window ow = occluder_window(fit.obox, fit.light, res);
    std::vector<Image<float>> omaps;
    omaps.push_back(ssm::render_light_map(scene, fit.occ, fit.light, ow,
                                          ssm::MapFaces::front_nearest, fit.near));
    if (two_pass_)
      omaps.push_back(ssm::render_light_map(
          scene, fit.occ, fit.light, ow,
          back_furthest_ ? ssm::MapFaces::back_furthest : ssm::MapFaces::back_nearest, fit.near));
    double zo_min = kInfinity;
    for (const Image<float>& m : omaps)
      for (float d : m.pixels())
        if (d < kInfinity) {
          zo_min = std::min(zo_min, static_cast<double>(d));
          ++out.occluder_texels;
        }
    occluder_stage.stop();
    if (!(zo_min < fit.zr_max)) return out;
    out.sw = ssm_window(ow, fit.rbox, fit.light, zo_min, fit.zr_max, ssm_res_);
    if (out.sw.empty()) return out;
    {
      ScopedStage stage(times, "receiver_map");
      out.rmap = ssm::render_light_map(scene, fit.rec, fit.light, out.sw,
                                       ssm::MapFaces::all_nearest, fit.near);
    }
    ScopedStage stage(times, "patches");
    for (size_t pass = 0; pass < omaps.size(); ++pass) {
      out.patches[pass] =
          make_patches(omaps[pass], ow, out.sw, fit.light, fit.zr_max, merge_ && !fp16_);
      for (const Patch& p : out.patches[pass])
        out.work += static_cast<double>(p.i1 - p.i0 + 1) * (p.j1 - p.j0 + 1);
    }
    return out;
  }

  /// Micro-patches of one occluder map [Atty 2006 §3.2] and their penumbra extents [§3.3].
  /// With `merge`, each maximal rectangle of texels of one depth (a face parallel to the light) is
  /// one patch: the back-projections of abutting patches at one depth abut on the light, so their
  /// clamped interval overlaps telescope and the rectangle hides exactly the sum of its texels
  /// (§3.4's product of two overlaps, summed over rows and columns). The answer is the same; the
  /// cost, occluder texels × extent (§5.1), falls by the rectangle's texel count.
  static std::vector<Patch> make_patches(const Image<float>& omap, const Window& ow,
                                         const Window& sw, const LightRect& light, double zr_max,
                                         bool merge) {
    struct Rect {
      int i0, i1, j0, j1;
      float zo;
    };
    std::vector<Rect> rects, open, row;
    for (int j = 0; j < ow.h; ++j) {
      row.clear();
      for (int i = 0; i < ow.w; ++i) {
        const float zo = omap(i, j);
        if (!(zo < zr_max)) continue;
        if (merge && !row.empty() && row.back().i1 == i - 1 && row.back().zo == zo)
          row.back().i1 = i;
        else
          row.push_back({i, i, j, j, zo});
      }
      // A run continues the rectangle above it when both span the same columns at the same depth
      // (both lists are sorted by column and disjoint).
      size_t k = 0;
      for (Rect& r : row) {
        if (!merge) break;
        while (k < open.size() && open[k].i0 < r.i0) ++k;
        if (k < open.size() && open[k].i0 == r.i0 && open[k].i1 == r.i1 && open[k].zo == r.zo) {
          r.j0 = open[k].j0;
          open[k].j1 = -1;  // continued by r
        }
      }
      for (const Rect& r : open)  // not continued: complete
        if (r.j1 >= 0) rects.push_back(r);
      open.swap(row);
    }
    rects.insert(rects.end(), open.begin(), open.end());
    std::vector<Patch> out;
    out.reserve(rects.size());
    for (const Rect& r : rects) {
      Patch p;
      p.order_i = r.i0;
      p.order_j = r.j0;
      p.zo = r.zo;
      // §3.2: the texels' image at depth z_O, in a plane parallel to the light.
      const double tx = ow.tx0 + 0.5 * (r.i0 + r.i1 + 1) * ow.dx();
      const double ty = ow.ty1 - 0.5 * (r.j0 + r.j1 + 1) * ow.dy();
      p.px = p.zo * tx;
      p.py = p.zo * ty;
      p.hx = 0.5 * p.zo * ow.dx() * (r.i1 - r.i0 + 1);
      p.hy = 0.5 * p.zo * ow.dy() * (r.j1 - r.j0 + 1);
      // §3.3: the penumbra extent is the pyramid from the light through the patch, apex O at depth
      // z_a = z_O·r/(1+r), r = LL'/PP', cut at the farthest receiver depth z_R: width
      // RR' = LL'·(z_R − z_a)/z_a, centred on the patch's own tangent. (The paper prints
      // z_R/(z_R − z_O) for the first factor; with depths from the light plane the similar
      // triangles give z_R/z_a, which is what matches the back-projection of §3.4.) Per axis, in
      // tangent units, that is h/z_O + L/2·(1/z_O − 1/z_R): a merged patch has its own aspect.
      const double ex = p.hx / p.zo + 0.5 * light.lu * (1.0 / p.zo - 1.0 / zr_max);
      const double ey = p.hy / p.zo + 0.5 * light.lv * (1.0 / p.zo - 1.0 / zr_max);
      // Texel centres inside [t − e, t + e]; clamped in double before the integer cast (an
      // occluder touching the light has an unbounded extent, §4.1.2).
      const auto lo = [](double c) { return std::clamp(std::ceil(c - 0.5), -1.0, 1e9); };
      const auto hi = [](double c) { return std::clamp(std::floor(c - 0.5), -1.0, 1e9); };
      const double u0 = lo(sw.to_u(tx - ex)), u1 = hi(sw.to_u(tx + ex));
      const double v0 = lo(sw.to_v(ty + ey)), v1 = hi(sw.to_v(ty - ey));
      p.i0 = static_cast<int>(std::max(u0, 0.0));
      p.i1 = static_cast<int>(std::min(u1, sw.w - 1.0));
      p.j0 = static_cast<int>(std::max(v0, 0.0));
      p.j1 = static_cast<int>(std::min(v1, sw.h - 1.0));
      if (p.i0 > p.i1 || p.j0 > p.j1) continue;
      out.push_back(p);
    }
    // Occluder-map order (row-major by the first texel): the blending order.
    std::sort(out.begin(), out.end(), [&](const Patch& a, const Patch& b) {
      return std::tie(a.order_j, a.order_i) < std::tie(b.order_j, b.order_i);
    });
    return out;
  }

  ssm::Blend blend_;  // step 4 elsewhere (the Vulkan backend), or null: the loop above
  int res_, ssm_res_;
  bool two_pass_, back_furthest_, fp16_, merge_;
  double budget_;  // soft-shadow-map texel updates per frame
};

}  // namespace

std::unique_ptr<ShadowMethod> ssm::make_ssm(const MethodOptions& options, Blend blend) {
  return std::make_unique<Ssm>(options, std::move(blend));
}

void register_ssm(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "ssm";
  info.summary =
      "soft shadow maps: occluder-map texels as light-parallel micro-patches, back-projected onto "
      "the rectangular light (one- or two-pass); alpha-textured (perforated) occluders count as "
      "opaque";
  info.reference = "[Atty 2006 §3, §3.5]";
  info.options = {
      {"resolution", OptionType::integer, "128", "occluder map side in texels", {}, 4, 4096},
      {"ssm_resolution",
       OptionType::integer,
       "256",
       "soft shadow map (and receiver map) side in texels",
       {},
       8,
       8192},
      {"two_pass",
       OptionType::boolean,
       "true",
       "add the back-face occluder map and merge with max (§3.5)",
       {}},
      {"back_depth",
       OptionType::choice,
       "furthest",
       "two-pass back-face map keeps the furthest or the nearest back face",
       {"furthest", "nearest"}},
      {"fp16",
       OptionType::boolean,
       "false",
       "round every blend to binary16 (the 2006 GPUs' blending, appendix A)",
       {}},
      {"merge",
       OptionType::boolean,
       "true",
       "one micro-patch per rectangle of equal-depth texels (same answer; off under fp16, whose "
       "rounding is per blend)",
       {}},
      {"budget",
       OptionType::integer,
       "300",
       "soft-shadow-map texel updates allowed per frame, in millions; above it the occluder map "
       "resolution is halved (§5.1)",
       {},
       1,
       1000000},
  };
  info.create = [](const MethodOptions& o) { return std::make_unique<Ssm>(o, nullptr); };
  registry.add(std::move(info));
}

}  // namespace penumbra
