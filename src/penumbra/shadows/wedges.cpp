#include "penumbra/shadows/wedges.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "penumbra/core/parallel.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/shadows/exact_projection.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/shadow_volume.hpp"
#include "penumbra/shadows/wedge_coverage.hpp"
#include "penumbra/shadows/wedge_geometry.hpp"
#include "penumbra/shadows/wedge_screen.hpp"

namespace penumbra {

namespace {

constexpr int kTile = 16;  // pixels per tile side: wedges are binned to tiles, pixels walk tiles

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

/// Points whose convex hull holds every emitting point of the light from any receiver.
std::vector<DVec3> light_hull_points(const Light& light) {
  std::vector<DVec3> pts;
  if (light.shape == LightShape::point) return pts;
  if (light.shape == LightShape::sphere) {
    const double r = light.radius;
    for (int k = 0; k < 8; ++k)
      pts.push_back(DVec3(light.center) +
                    r * DVec3(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0));
    return pts;
  }
  const LightFrame f = light_frame(light, light.center);  // constant for rect and disk
  for (int k = 0; k < 4; ++k)
    pts.push_back(DVec3(f.corner) + (k & 1 ? 1.0 : 0.0) * DVec3(f.edge_u) +
                  (k & 2 ? 1.0 : 0.0) * DVec3(f.edge_v));
  return pts;
}

/// 2 for a closed, consistently oriented mesh (every segment crosses it an even number of times),
/// 1 otherwise.
int mesh_layers(const MeshEdges& e) {
  return e.closed_manifold() ? 2 : 1;
}

/// Pass 1 [paper III §3.2, Forest Algorithm 3 line 1]: Σ over meshes of count / layers, from the
/// hard-shadow point. One shadow_volume_counts call per distinct layer count.
Image<float> layered_counts(const ShadowContext& ctx, const Vec3& point,
                            const std::vector<int>& layers) {
  const GBuffer& g = ctx.gbuffer;
  Image<float> out(g.width, g.height, 0.0f);
  for (int l : {1, 2}) {
    bool any = false, all = true;
    for (size_t m = 0; m < ctx.scene.meshes.size(); ++m) {
      if (layers[m] == 0) continue;
      any |= layers[m] == l;
      all &= layers[m] == l;
    }
    if (!any) continue;
    Image<int32_t> counts;
    if (all) {
      counts = shadow_volume_counts(ctx.scene, ctx.scene.camera, g, ctx.receivers, point);
    } else {
      Scene part = ctx.scene;
      for (size_t m = 0; m < part.meshes.size(); ++m) part.meshes[m].casts_shadows = layers[m] == l;
      counts = shadow_volume_counts(part, part.camera, g, ctx.receivers, point);
    }
    for (size_t i = 0; i < counts.size(); ++i)
      out[i] += static_cast<float>(counts[i]) / static_cast<float>(l);
  }
  return out;
}

/// Per-pixel data shared by all wedges of a frame.
struct PixelSetup {
  WedgeScreenSetup screen;
  double margin = 0.0;  // max offset between a shadow origin's projection and its pixel centre
  bool any_active = false;
};

PixelSetup pixel_setup(const ShadowContext& ctx) {
  const GBuffer& g = ctx.gbuffer;
  Camera cam = ctx.scene.camera;
  cam.width = g.width;
  cam.height = g.height;
  PixelSetup s;
  s.screen.proj = camera_projection(cam);
  std::vector<double> row_margin(g.height, 0.0), row_near(g.height, kInfinity),
      row_far(g.height, 0.0);
  std::vector<uint8_t> row_any(g.height, 0);
  parallel_rows(g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (ctx.receivers[i] != kActive) continue;
      const DVec4 c = s.screen.proj.to_clip(DVec4(DVec3(g.shadow_origin(i)), 1.0));
      if (!(c.w > 0.0)) continue;
      const DVec3 p = s.screen.proj.to_screen(c);
      row_margin[y] =
          std::max({row_margin[y], std::abs(p.x - (x + 0.5)), std::abs(p.y - (y + 0.5))});
      row_near[y] = std::min(row_near[y], c.w);
      row_far[y] = std::max(row_far[y], c.w);
      row_any[y] = 1;
    }
  });
  s.any_active = std::find(row_any.begin(), row_any.end(), 1) != row_any.end();
  if (!s.any_active) return s;
  s.margin = std::ceil(*std::max_element(row_margin.begin(), row_margin.end())) + 1.0;
  s.screen.near_depth = 0.5 * *std::min_element(row_near.begin(), row_near.end());
  s.screen.far_depth = 2.0 * *std::max_element(row_far.begin(), row_far.end());
  return s;
}

/// One light (or sub-light): pass 1, silhouettes, wedges, pass 2. Returns V per pixel.
Image<float> visibility_for_light(const ShadowContext& ctx, const Light& light,
                                  const PixelSetup& setup, WedgeStats& st) {
  const GBuffer& g = ctx.gbuffer;
  const Scene& scene = ctx.scene;
  const Vec3 centre = hard_shadow_point(light);

  // Silhouette edges from the light centre [paper III §3.1], one wedge each.
  auto start = std::chrono::steady_clock::now();
  std::vector<int> layers(scene.meshes.size(), 0);
  struct EdgeRef {
    DVec3 from, to;
    double weight;
  };
  std::vector<EdgeRef> sil;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.casts_shadows || mesh.triangles.empty()) continue;
    const MeshEdges edges = build_mesh_edges(mesh);
    layers[m] = mesh_layers(edges);
    for (const SilhouetteEdge& s : point_silhouette(mesh, edges, centre))
      sil.push_back({DVec3(mesh.positions[s.from]), DVec3(mesh.positions[s.to]),
                     static_cast<double>(s.multiplicity) / layers[m]});
  }
  st.silhouette_edges += sil.size();
  st.silhouettes_ms += ms_since(start);

  start = std::chrono::steady_clock::now();
  const Image<float> count = layered_counts(ctx, centre, layers);
  st.pass1_ms += ms_since(start);

  Image<float> vis(g.width, g.height, 1.0f);
  const std::vector<DVec3> hull = light_hull_points(light);
  if (hull.empty() || sil.empty() || !setup.any_active) {  // point light: hard shadows
    for (size_t i = 0; i < vis.size(); ++i)
      if (ctx.receivers[i] == kActive) vis[i] = 1.0f - std::clamp(count[i], 0.0f, 1.0f);
    return vis;
  }

  // Wedges and their screen hulls.
  start = std::chrono::steady_clock::now();
  const double scale = std::max(1.0, static_cast<double>(scene.bounds().diagonal()));
  std::vector<Wedge> wedges(sil.size());
  std::vector<std::vector<DVec2>> hulls(sil.size());
  std::vector<DVec2> yrange(sil.size());
  parallel_chunks(sil.size(), 64, [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) {
      wedges[k] = build_wedge(sil[k].from, sil[k].to, sil[k].weight, hull, DVec3(centre), scale);
      hulls[k] = wedge_screen_hull(setup.screen, sil[k].from, sil[k].to, hull);
      yrange[k] = DVec2(kInfinity, -kInfinity);
      for (const DVec2& p : hulls[k])
        yrange[k] = DVec2(std::min(yrange[k].x, p.y), std::max(yrange[k].y, p.y));
    }
  });
  st.wedges += wedges.size();

  // Bin wedges to tiles, one tile row per task (deterministic order: wedge index).
  const int tiles_x = (g.width + kTile - 1) / kTile, tiles_y = (g.height + kTile - 1) / kTile;
  std::vector<std::vector<uint32_t>> bins(static_cast<size_t>(tiles_x) * tiles_y);
  const double margin = setup.margin;
  parallel_rows(tiles_y, [&](int ty) {
    const double y0 = ty * kTile + 0.5 - margin,
                 y1 = std::min(g.height, (ty + 1) * kTile) - 0.5 + margin;
    for (uint32_t k = 0; k < wedges.size(); ++k) {
      if (yrange[k].y < y0 || yrange[k].x > y1) continue;
      double x0 = 0.0, x1 = 0.0;
      if (!hull_row_span(hulls[k], y0, y1, x0, x1)) continue;
      const double ta = std::floor((x0 - margin - 0.5) / kTile),
                   tb = std::floor((x1 + margin - 0.5) / kTile);
      if (tb < 0.0 || ta > tiles_x - 1.0) continue;
      const int a = static_cast<int>(std::max(0.0, ta)),
                b = static_cast<int>(std::min(tiles_x - 1.0, tb));
      for (int tx = a; tx <= b; ++tx) bins[static_cast<size_t>(ty) * tiles_x + tx].push_back(k);
    }
  });
  st.wedges_ms += ms_since(start);

  // Pass 2 [paper III §3.2; Forest Algorithm 3]: per pixel, every wedge of its tile.
  start = std::chrono::steady_clock::now();
  const bool per_pixel_frame = light.shape == LightShape::sphere;
  const LightFrame fixed_frame = light_frame(light, light.center);
  std::atomic<uint64_t> tests{0}, inside{0}, covered{0}, fallbacks{0};
  parallel_rows(tiles_y, [&](int ty) {
    uint64_t n_tests = 0, n_inside = 0, n_covered = 0, n_fallback = 0;
    for (int tx = 0; tx < tiles_x; ++tx) {
      const std::vector<uint32_t>& bin = bins[static_cast<size_t>(ty) * tiles_x + tx];
      for (int y = ty * kTile; y < std::min(g.height, (ty + 1) * kTile); ++y) {
        for (int x = tx * kTile; x < std::min(g.width, (tx + 1) * kTile); ++x) {
          const size_t i = static_cast<size_t>(y) * g.width + x;
          if (ctx.receivers[i] != kActive) continue;
          double sum = count[i];
          if (!bin.empty()) {
            const Vec3 origin = g.shadow_origin(i);
            const DVec3 p(origin);
            const LightFrame f = per_pixel_frame ? light_frame(light, origin) : fixed_frame;
            LightProjection lp;
            if (!make_light_projection(p, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), lp)) {
              ++n_fallback;
            } else {
              // τ: orientation of light uv as seen from p; with it the sign of (c, a, b) in uv
              // tells the inner half (−) from the outer half (+) [wedge_coverage.hpp].
              const double tau =
                  glm::dot(lp.to_w, glm::cross(DVec3(f.edge_u), DVec3(f.edge_v))) > 0.0 ? 1.0
                                                                                        : -1.0;
              const double inv_area = 1.0 / f.uv_area();
              for (uint32_t k : bin) {
                const Wedge& w = wedges[k];
                ++n_tests;
                if (!w.contains(p)) continue;
                ++n_inside;
                DVec2 a, b;
                if (!clip_edge_to_light_square(lp.homogeneous(w.e0), lp.homogeneous(w.e1), a, b))
                  continue;
                if (f.round && !clip_edge_to_light_disk(a, b)) continue;
                const double area =
                    f.round ? disk_sector_minus_triangle(a, b) : square_sector_minus_triangle(a, b);
                if (area == 0.0) continue;
                ++n_covered;
                sum -= tau * w.weight * area * inv_area;
              }
            }
          }
          vis[i] = static_cast<float>(1.0 - std::clamp(sum, 0.0, 1.0));
        }
      }
    }
    tests += n_tests;
    inside += n_inside;
    covered += n_covered;
    fallbacks += n_fallback;
  });
  st.pixel_tests += tests.load();
  st.pixels_inside += inside.load();
  st.pixels_covered += covered.load();
  st.plane_fallbacks += fallbacks.load();
  st.pass2_ms += ms_since(start);
  return vis;
}

}  // namespace

Image<float> wedge_visibility(const ShadowContext& ctx, const WedgeOptions& options,
                              WedgeStats* stats_out) {
  WedgeStats st;
  const PixelSetup setup = pixel_setup(ctx);
  const Light& light = ctx.light;
  // Light splitting [paper IV §5.2]: rectangles only (a sub-square of a disk is not a disk).
  const int n = light.shape == LightShape::rect ? std::max(1, options.split) : 1;
  Image<float> vis;
  if (n == 1) {
    vis = visibility_for_light(ctx, light, setup, st);
    st.sub_lights = 1;
  } else {
    vis = Image<float>(ctx.gbuffer.width, ctx.gbuffer.height, 0.0f);
    const Vec3 corner = light.center - 0.5f * (light.edge_u + light.edge_v);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        Light sub = light;
        sub.edge_u = light.edge_u / static_cast<float>(n);
        sub.edge_v = light.edge_v / static_cast<float>(n);
        sub.center = corner + (static_cast<float>(i) + 0.5f) * sub.edge_u +
                     (static_cast<float>(j) + 0.5f) * sub.edge_v;
        const Image<float> part = visibility_for_light(ctx, sub, setup, st);
        for (size_t k = 0; k < vis.size(); ++k) vis[k] += part[k] / static_cast<float>(n * n);
      }
    }
    st.sub_lights = static_cast<size_t>(n) * n;
  }
  if (stats_out) *stats_out = st;
  return vis;
}

namespace {

class Wedges final : public ShadowMethod {
 public:
  explicit Wedges(WedgeOptions options) : options_(options) {}

  Visibility compute(const ShadowContext& ctx) override {
    WedgeStats st;
    Visibility v;
    v.lit = wedge_visibility(ctx, options_, &st);
    v.times.add("silhouettes", st.silhouettes_ms);
    v.times.add("pass1", st.pass1_ms);
    v.times.add("wedges", st.wedges_ms);
    v.times.add("pass2", st.pass2_ms);
    v.counters["silhouette_edges"] = static_cast<double>(st.silhouette_edges);
    v.counters["wedges"] = static_cast<double>(st.wedges);
    v.counters["sub_lights"] = static_cast<double>(st.sub_lights);
    v.counters["pixel_tests"] = static_cast<double>(st.pixel_tests);
    v.counters["pixels_inside_wedges"] = static_cast<double>(st.pixels_inside);
    v.counters["pixels_covered"] = static_cast<double>(st.pixels_covered);
    v.counters["light_plane_fallbacks"] = static_cast<double>(st.plane_fallbacks);
    return v;
  }

 private:
  WedgeOptions options_;
};

}  // namespace

void register_wedges(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "wedges";
  info.summary =
      "soft shadow volumes: hard count from the light centre plus analytic penumbra-wedge "
      "coverage per silhouette edge (rectangle, disk, sphere lights)";
  info.reference = "[seed 000 papers III §3, IV §4–5; Forest thesis §3.1, App. 3.B]";
  info.sample_exact = false;
  info.options = {
      {"split",
       OptionType::integer,
       "1",
       "split a rectangular light into split x split sub-lights (paper IV 5.2); ignored for round "
       "lights",
       {},
       1,
       16},
  };
  info.create = [](const MethodOptions& o) {
    WedgeOptions w;
    w.split = o.get_int("split");
    return std::make_unique<Wedges>(w);
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
