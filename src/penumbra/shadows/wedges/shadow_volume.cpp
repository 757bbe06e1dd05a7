#include "penumbra/shadows/wedges/shadow_volume.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

constexpr int kBand = 8;             // rows per parallel task
constexpr size_t kFaceChunk = 4096;  // triangles per setup task

/// Tie rule for a pixel exactly on an edge plane: antisymmetric (owns(n) != owns(−n) for n ≠ 0).
bool owns(const DVec3& n) {
  return n.x > 0.0 || (n.x == 0.0 && (n.y > 0.0 || (n.y == 0.0 && n.z > 0.0)));
}

/// One face of the summed shadow volume, ready for per-pixel tests with q = p − camera.
struct Face {
  int n = 0;
  DVec3 edge[4];  // q inside the face's cone iff dot(edge[i], q) > 0, or == 0 with own bit i
  uint8_t own = 0;
  bool has_plane = false;  // far caps (at infinity) have none: always behind p
  DVec3 plane_n{0.0};
  double plane_k = 0.0;  // the face is behind p iff (dot(plane_n, q) + plane_k) · plane_k > 0
  int32_t weight = 0;    // +|w| back-facing from the camera (ray leaves), −|w| front-facing
  ScreenPolygon poly;
};

/// Vertex ids: 2·g for caster vertex g (finite), 2·g + 1 for its extrusion to infinity.
class VolumeBuilder {
 public:
  VolumeBuilder(const std::vector<DVec3>& positions, const DVec3& camera, const DVec3& light,
                const Projection& proj, double near, double guard, double margin)
      : pos_(positions),
        cam_(camera),
        light_(light),
        proj_(proj),
        near_(near),
        guard_(guard),
        margin_(margin) {}

  /// Builds the face on vertex ids[0..n) (n = 3 or 4); false if seen edge-on or off screen.
  bool make(const uint32_t* ids, int n, int32_t weight, const DVec3* plane_n, double plane_k,
            Face& f) const {
    // Screen extent first: most far caps and many caps are culled here, before any plane setup.
    DVec4 world[4];
    for (int i = 0; i < n; ++i)
      world[i] =
          (ids[i] & 1u) ? DVec4(pos_[ids[i] >> 1] - light_, 0.0) : DVec4(pos_[ids[i] >> 1], 1.0);
    f.poly = project_polygon(proj_, world, n, near_, guard_);
    if (f.poly.empty() || f.poly.xmax < -margin_ || f.poly.ymax < -margin_ ||
        f.poly.xmin > proj_.width + margin_ || f.poly.ymin > proj_.height + margin_)
      return false;
    const double det = glm::dot(glm::cross(dir(ids[0]), dir(ids[1])), dir(ids[2]));
    if (!(det != 0.0)) return false;
    const double s = det > 0.0 ? 1.0 : -1.0;
    f.n = n;
    f.own = 0;
    for (int i = 0; i < n; ++i) {
      f.edge[i] = s * edge_normal(ids[i], ids[(i + 1) % n]);
      if (owns(f.edge[i])) f.own |= static_cast<uint8_t>(1u << i);
    }
    f.weight = static_cast<int32_t>(s) * weight;
    f.has_plane = plane_n != nullptr;
    if (plane_n) {
      f.plane_n = *plane_n;
      f.plane_k = plane_k;
      if (!(plane_k != 0.0)) return false;  // camera in the face's plane: seen edge-on
    }
    return true;
  }

 private:
  DVec3 dir(uint32_t id) const { return (id & 1u) ? pos_[id >> 1] - light_ : pos_[id >> 1] - cam_; }
  /// The plane through the camera containing edge a → b: computed from the ids in canonical order.
  DVec3 edge_normal(uint32_t a, uint32_t b) const {
    const uint32_t lo = std::min(a, b), hi = std::max(a, b);
    const DVec3 nrm = glm::cross(dir(lo), dir(hi));
    return a == lo ? nrm : -nrm;
  }

  const std::vector<DVec3>& pos_;
  DVec3 cam_, light_;
  const Projection& proj_;
  double near_, guard_, margin_;
};

}  // namespace

ShadowVolumePixels shadow_volume_pixels(const Camera& camera, const GBuffer& g,
                                        const Image<uint8_t>& receivers) {
  ShadowVolumePixels px;
  Camera cam = camera;
  cam.width = g.width;
  cam.height = g.height;
  px.proj = camera_projection(cam);
  const DVec3 C = px.proj.eye;
  px.q.resize(g.pixel_count());
  std::atomic<int> any_active{0};
  std::vector<double> row_margin(g.height, 0.0), row_near(g.height, kInfinity);
  parallel_rows(g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (receivers[i] != kActive) continue;
      px.q[i] = DVec3(g.shadow_origin(i)) - C;
      const DVec4 c = px.proj.to_clip(DVec4(px.q[i] + C, 1.0));
      if (!(c.w > 0.0)) continue;  // cannot happen for a visible point
      const DVec3 s = px.proj.to_screen(c);
      row_margin[y] =
          std::max({row_margin[y], std::abs(s.x - (x + 0.5)), std::abs(s.y - (y + 0.5))});
      row_near[y] = std::min(row_near[y], c.w);
      any_active.store(1, std::memory_order_relaxed);
    }
  });
  px.any_active = any_active.load() != 0;
  if (!px.any_active) return px;
  px.margin = std::ceil(*std::max_element(row_margin.begin(), row_margin.end())) + 1.0;
  px.near = 0.5 * *std::min_element(row_near.begin(), row_near.end());
  px.guard = 1.0 + 2.0 * (px.margin + 1.0) / std::min(g.width, g.height);
  return px;
}

Image<int32_t> shadow_volume_counts(const Scene& scene, const Camera& camera, const GBuffer& g,
                                    const Image<uint8_t>& receivers, const Vec3& light_point,
                                    ShadowVolumeStats* stats_out) {
  const auto start = std::chrono::steady_clock::now();
  const ShadowVolumePixels px = shadow_volume_pixels(camera, g, receivers);
  const double pixels_ms = elapsed_ms(start);
  Image<int32_t> counts = shadow_volume_counts(scene, px, g, receivers, light_point, stats_out);
  if (stats_out) stats_out->edges_ms += pixels_ms;
  return counts;
}

Image<int32_t> shadow_volume_counts(const Scene& scene, const ShadowVolumePixels& px,
                                    const GBuffer& g, const Image<uint8_t>& receivers,
                                    const Vec3& light_point, ShadowVolumeStats* stats_out) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<const Mesh*> meshes;
  for (const Mesh& m : scene.meshes)
    if (m.casts_shadows && !m.triangles.empty()) meshes.push_back(&m);
  std::vector<MeshEdges> edges(meshes.size());
  parallel_chunks(meshes.size(), 1, [&](size_t a, size_t b) {
    for (size_t k = a; k < b; ++k) edges[k] = build_mesh_edges(*meshes[k]);
  });
  std::vector<CountCaster> casters;
  for (size_t k = 0; k < meshes.size(); ++k) casters.push_back({meshes[k], &edges[k]});
  const double edges_ms = elapsed_ms(start);
  Image<int32_t> counts = shadow_volume_counts(casters, px, g, receivers, light_point, stats_out);
  if (stats_out) stats_out->edges_ms += edges_ms;
  return counts;
}

Image<int32_t> shadow_volume_counts(std::span<const CountCaster> casters,
                                    const ShadowVolumePixels& px, const GBuffer& g,
                                    const Image<uint8_t>& receivers, const Vec3& light_point,
                                    ShadowVolumeStats* stats_out) {
  ShadowVolumeStats stats;
  Image<int32_t> counts(g.width, g.height, 0);
  if (!px.any_active) return counts;
  const Projection& proj = px.proj;
  const DVec3 C = proj.eye, L(light_point);
  const std::vector<DVec3>& q = px.q;
  const double margin = px.margin, near = px.near, guard = px.guard;

  auto start = std::chrono::steady_clock::now();
  // Caster vertices (welded), per-face sides and silhouettes.
  std::vector<DVec3> pos;
  struct MeshData {
    const Mesh* mesh;
    const MeshEdges& edges;
    std::vector<int8_t> sides;
    std::vector<SilhouetteEdge> silhouette;
    uint32_t base;
  };
  std::vector<MeshData> meshes;
  for (const CountCaster& c : casters) {
    const Mesh& m = *c.mesh;
    if (m.triangles.empty()) continue;
    MeshData d{&m, *c.edges, {}, {}, static_cast<uint32_t>(pos.size())};
    for (const Vec3& p : m.positions) pos.push_back(DVec3(p));
    d.sides = face_sides(m, d.edges, light_point);
    size_t kept = d.sides.size();
    if (c.keep) {
      // A face left out is edge-on to the count: no cap, no weight in any silhouette edge's
      // multiplicity (the sum of side × orientation over its faces), so the count is the kept
      // sub-mesh's, with the whole mesh's adjacency.
      kept = 0;
      for (size_t f = 0; f < d.sides.size(); ++f) {
        if (!(*c.keep)[f]) d.sides[f] = 0;
        kept += (*c.keep)[f] != 0;
      }
    }
    d.silhouette = silhouette_from_sides(d.edges, d.sides);
    stats.caster_triangles += kept;
    stats.silhouette_edges += d.silhouette.size();
    meshes.push_back(std::move(d));
  }
  stats.edges_ms = elapsed_ms(start);

  start = std::chrono::steady_clock::now();
  const VolumeBuilder builder(pos, C, L, proj, near, guard, margin);
  std::vector<Face> faces;
  std::atomic<size_t> built{0};
  for (const MeshData& d : meshes) {
    const size_t nf = d.edges.faces.size();
    const size_t chunks = (nf + kFaceChunk - 1) / kFaceChunk;
    std::vector<std::vector<Face>> per_chunk(chunks);
    parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
      for (size_t c = c0; c < c1; ++c) {
        size_t local_built = 0;
        for (size_t f = c * kFaceChunk; f < std::min(nf, (c + 1) * kFaceChunk); ++f) {
          const int side = d.sides[f];
          if (side == 0) continue;
          const auto& w = d.edges.faces[f];
          // Near cap oriented toward the light, far cap the reverse at infinity.
          const uint32_t a = d.base + w[0], b = d.base + (side > 0 ? w[1] : w[2]),
                         cc = d.base + (side > 0 ? w[2] : w[1]);
          const uint32_t cap[3] = {2 * a, 2 * b, 2 * cc};
          const uint32_t far_cap[3] = {2 * a + 1, 2 * cc + 1, 2 * b + 1};
          const DVec3 n = glm::cross(pos[b] - pos[a], pos[cc] - pos[a]);
          Face face;
          if (builder.make(cap, 3, 1, &n, glm::dot(n, C - pos[a]), face))
            per_chunk[c].push_back(face);
          if (builder.make(far_cap, 3, 1, nullptr, 0.0, face)) per_chunk[c].push_back(face);
          local_built += 2;
        }
        built += local_built;
      }
    });
    for (auto& v : per_chunk) faces.insert(faces.end(), v.begin(), v.end());
    for (const SilhouetteEdge& s : d.silhouette) {
      // The cap traverses from → to, so the side quad is (to, from, ∞from, ∞to).
      const uint32_t from = d.base + s.from, to = d.base + s.to;
      const uint32_t quad[4] = {2 * to, 2 * from, 2 * from + 1, 2 * to + 1};
      const DVec3 n = glm::cross(pos[from] - L, pos[to] - L);
      Face face;
      if (builder.make(quad, 4, s.multiplicity, &n, glm::dot(n, C - L), face))
        faces.push_back(face);
      built += 1;
    }
  }
  stats.faces = built.load();
  stats.faces_on_screen = faces.size();

  // Bin faces into bands of rows.
  const int bands = (g.height + kBand - 1) / kBand;
  std::vector<std::vector<uint32_t>> bins(bands);
  std::vector<std::pair<int, int>> face_rows(faces.size());
  for (uint32_t i = 0; i < faces.size(); ++i) {
    const ScreenPolygon& p = faces[i].poly;
    const int y0 =
        static_cast<int>(std::clamp(std::floor(p.ymin - margin - 0.5), 0.0, g.height - 1.0));
    const int y1 =
        static_cast<int>(std::clamp(std::ceil(p.ymax + margin - 0.5), 0.0, g.height - 1.0));
    face_rows[i] = {y0, y1};
    for (int b = y0 / kBand; b <= y1 / kBand; ++b) bins[b].push_back(i);
  }
  stats.setup_ms = elapsed_ms(start);

  start = std::chrono::steady_clock::now();
  std::atomic<uint64_t> tests{0};
  parallel_bands(g.height, kBand, [&](int first, int last) {
    uint64_t local_tests = 0;
    for (uint32_t fi : bins[first / kBand]) {
      const Face& f = faces[fi];
      const int y_begin = std::max(first, face_rows[fi].first),
                y_end = std::min(last - 1, face_rows[fi].second);
      for (int y = y_begin; y <= y_end; ++y) {
        double x0 = 0.0, x1 = 0.0;
        if (!polygon_row_span(f.poly, y + 0.5 - margin, y + 0.5 + margin, x0, x1)) continue;
        const int xa =
            static_cast<int>(std::clamp(std::ceil(x0 - margin - 0.5), 0.0, g.width - 1.0));
        const int xb =
            static_cast<int>(std::clamp(std::floor(x1 + margin - 0.5), 0.0, g.width - 1.0));
        if (x1 + margin - 0.5 < 0.0 || x0 - margin - 0.5 > g.width - 1.0) continue;
        const size_t row = static_cast<size_t>(y) * g.width;
        for (int x = xa; x <= xb; ++x) {
          const size_t i = row + x;
          if (receivers[i] != kActive) continue;
          ++local_tests;
          const DVec3& qi = q[i];
          bool inside = true;
          for (int e = 0; e < f.n; ++e) {
            const double d = glm::dot(f.edge[e], qi);
            if (d < 0.0 || (d == 0.0 && !((f.own >> e) & 1u))) {
              inside = false;
              break;
            }
          }
          if (!inside) continue;
          if (f.has_plane && !((glm::dot(f.plane_n, qi) + f.plane_k) * f.plane_k > 0.0)) continue;
          counts[i] += f.weight;
        }
      }
    }
    tests += local_tests;
  });
  stats.pixel_tests = tests.load();
  stats.count_ms = elapsed_ms(start);
  if (stats_out) *stats_out = stats;
  return counts;
}

Image<int32_t> shadow_volume_counts(const ShadowContext& ctx, ShadowVolumeStats* stats) {
  return shadow_volume_counts(ctx.scene, ctx.scene.camera, ctx.gbuffer, ctx.receivers,
                              hard_shadow_point(ctx.light), stats);
}

namespace {

class ShadowVolume final : public ShadowMethod {
 public:
  Visibility compute(const ShadowContext& ctx) override {
    ShadowVolumeStats stats;
    const Image<int32_t> counts = shadow_volume_counts(ctx, &stats);
    Visibility vis;
    vis.lit = Image<float>(ctx.gbuffer.width, ctx.gbuffer.height, 1.0f);
    size_t negative = 0, shadowed = 0;
    for (size_t i = 0; i < counts.size(); ++i) {
      if (ctx.receivers[i] != kActive) continue;
      negative += counts[i] < 0;
      shadowed += counts[i] > 0;
      vis.lit[i] = counts[i] > 0 ? 0.0f : 1.0f;
    }
    vis.times.add("edges", stats.edges_ms);
    vis.times.add("setup", stats.setup_ms);
    vis.times.add("count", stats.count_ms);
    vis.counters["silhouette_edges"] = static_cast<double>(stats.silhouette_edges);
    vis.counters["volume_faces"] = static_cast<double>(stats.faces);
    vis.counters["faces_on_screen"] = static_cast<double>(stats.faces_on_screen);
    vis.counters["pixel_tests"] = static_cast<double>(stats.pixel_tests);
    vis.counters["shadowed_pixels"] = static_cast<double>(shadowed);
    vis.counters["negative_count_pixels"] = static_cast<double>(negative);
    return vis;
  }
};

}  // namespace

void register_shadow_volume(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "shadow_volume";
  info.summary =
      "hard shadows from the light centre: exact z-fail shadow-volume counts per G-buffer pixel; "
      "alpha-textured (perforated) occluders count as opaque";
  info.reference = "[Forest 2008 §2.2.1, §3.3.1, App. 3.A; Assarsson 2003 V]";
  info.sample_exact = false;  // exact for the light centre only (raytrace with one centred sample)
  info.create = [](const MethodOptions&) { return std::make_unique<ShadowVolume>(); };
  registry.add(std::move(info));
}

}  // namespace penumbra
