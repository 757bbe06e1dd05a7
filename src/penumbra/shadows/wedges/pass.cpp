#include "penumbra/shadows/wedges/pass.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <numeric>
#include <string>
#include <unordered_set>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/orientation.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::wedge_pass {

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

WedgeLight wedge_light(const Light& light) {
  WedgeLight L;
  L.hull = light_hull_points(light);
  L.centre = DVec3(hard_shadow_point(light));
  if (light.shape == LightShape::disk || light.shape == LightShape::sphere) {
    L.round = true;
    L.radius = light.radius;
  }
  if ((light.shape == LightShape::rect || light.shape == LightShape::disk) && !light.two_sided) {
    const LightFrame f = light_frame(light, light.center);
    L.one_sided = true;
    L.disk = light.shape == LightShape::disk;
    L.normal = glm::normalize(DVec3(f.emit_normal));
    L.corner = DVec3(f.corner);
    L.edge_u = DVec3(f.edge_u);
    L.edge_v = DVec3(f.edge_v);
  }
  return L;
}

const Texture& emission_texture(const Scene& scene, const Light& light, const char* method) {
  if (light.emission_texture < 0 ||
      light.emission_texture >= static_cast<int>(scene.textures.size()))
    throw Error(std::string(method) + ": light '" + light.name + "' names emission texture " +
                std::to_string(light.emission_texture) + " of " +
                std::to_string(scene.textures.size()));
  return scene.textures[light.emission_texture];
}

float rgb_visibility(const DVec3& occluded, const DVec3& total, Vec3& rgb) {
  static constexpr double kLum[3] = {0.2126, 0.7152, 0.0722};
  double seen = 0.0, all = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double v = total[c] > 0.0 ? 1.0 - std::clamp(occluded[c], 0.0, 1.0) : 1.0;
    rgb[c] = static_cast<float>(v);
    seen += kLum[c] * total[c] * v;
    all += kLum[c] * total[c];
  }
  return all > 0.0 ? static_cast<float>(std::min(1.0, seen / all)) : 1.0f;
}

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
  s.tiles_x = (g.width + kTile - 1) / kTile;
  s.tiles_y = (g.height + kTile - 1) / kTile;
  s.tile_lo.assign(static_cast<size_t>(s.tiles_x) * s.tiles_y, DVec3(kInfinity));
  s.tile_hi.assign(s.tile_lo.size(), DVec3(-kInfinity));
  parallel_rows(s.tiles_y, [&](int ty) {
    for (int y = ty * kTile; y < std::min(g.height, (ty + 1) * kTile); ++y)
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (ctx.receivers[i] != kActive) continue;
        const size_t t = static_cast<size_t>(ty) * s.tiles_x + x / kTile;
        const DVec3 p(g.shadow_origin(i));
        s.tile_lo[t] = glm::min(s.tile_lo[t], p);
        s.tile_hi[t] = glm::max(s.tile_hi[t], p);
      }
  });
  s.any_active = std::find(row_any.begin(), row_any.end(), 1) != row_any.end();
  s.volume = shadow_volume_pixels(ctx.scene.camera, g, ctx.receivers);
  if (!s.any_active) return s;
  s.margin = std::ceil(*std::max_element(row_margin.begin(), row_margin.end())) + 1.0;
  s.screen.near_depth = 0.5 * *std::min_element(row_near.begin(), row_near.end());
  s.screen.far_depth = 2.0 * *std::max_element(row_far.begin(), row_far.end());
  return s;
}

namespace {

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// The light-facing patches of a mesh seen from `centre` (see wedges/pass.hpp), as open sub-meshes
/// holding only the positions they use. Faces seen edge-on (side 0) block nothing and belong to
/// no patch.
std::vector<std::unique_ptr<Mesh>> facing_patches(const Mesh& mesh, const MeshEdges& edges,
                                                  const Vec3& centre, bool closed) {
  const std::vector<int8_t> sides = face_sides(mesh, edges, centre);
  // A closed mesh crosses every segment from outside once toward the light per layer pair: its
  // light-facing faces alone give the count. An open mesh: every face counts, whichever side.
  auto kept = [&](size_t f) { return closed ? sides[f] > 0 : sides[f] != 0; };
  std::vector<uint32_t> parent(edges.faces.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const MeshEdge& e : edges.edges) {
    if (e.kind != EdgeKind::manifold || e.face_count != 2) continue;
    const uint32_t f = edges.edge_faces[e.face_begin].face;
    const uint32_t h = edges.edge_faces[e.face_begin + 1].face;
    if (!kept(f) || sides[f] != sides[h]) continue;
    const uint32_t rf = find_root(parent, f), rh = find_root(parent, h);
    if (rf != rh) parent[rh] = rf;
  }
  // Faces per patch, then one patch at a time through one vertex map (memory O(vertices)).
  std::vector<int32_t> patch_of_root(parent.size(), -1);
  std::vector<std::vector<uint32_t>> patch_faces;
  for (size_t f = 0; f < edges.faces.size(); ++f) {
    if (!edges.face_valid(f) || !kept(f)) continue;
    const uint32_t r = find_root(parent, static_cast<uint32_t>(f));
    if (patch_of_root[r] < 0) {
      patch_of_root[r] = static_cast<int32_t>(patch_faces.size());
      patch_faces.emplace_back();
    }
    patch_faces[patch_of_root[r]].push_back(static_cast<uint32_t>(f));
  }
  std::vector<std::unique_ptr<Mesh>> out;
  std::vector<uint32_t> local(mesh.positions.size()), stamp(mesh.positions.size(), ~0u);
  for (uint32_t p = 0; p < patch_faces.size(); ++p) {
    auto m = std::make_unique<Mesh>();
    m->name = mesh.name;
    m->material = mesh.material;
    for (const uint32_t f : patch_faces[p]) {
      Triangle tri{};
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = mesh.triangles[f].v[c];
        if (stamp[v] != p) {
          stamp[v] = p;
          local[v] = static_cast<uint32_t>(m->positions.size());
          m->positions.push_back(mesh.positions[v]);
        }
        tri.v[c] = local[v];
      }
      m->triangles.push_back(tri);
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

bool solid_for_wedges(const Mesh& mesh, const MeshEdges& e) {
  if (e.closed_manifold()) return true;
  if (e.edges.empty() || e.non_manifold_edges != 0 || e.inconsistent_edges != 0) return false;
  return hole_geometry(mesh, e).fraction() <= kHoleAreaFraction;
}

namespace {

/// A triangle's three positions as exact bits, in cyclic order from the smallest: equal for
/// coincident triangles of the same winding whatever their first vertex or mesh. Opposite windings
/// differ: a two-sided sheet's back faces and the touching faces of two boxes are kept.
using TriangleKey = std::array<uint32_t, 9>;
struct TriangleKeyHash {
  size_t operator()(const TriangleKey& k) const {
    uint64_t h = 0xcbf29ce484222325ull;
    for (uint32_t x : k) h = (h ^ x) * 0x100000001b3ull;
    return static_cast<size_t>(h ^ (h >> 31));
  }
};
TriangleKey triangle_key(const Mesh& mesh, const Triangle& t) {
  std::array<std::array<uint32_t, 3>, 3> p;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      p[c][k] = std::bit_cast<uint32_t>(mesh.positions[t.v[c]][k] + 0.0f);  // −0 → +0
  const int first = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
  TriangleKey key;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) key[3 * c + k] = p[(first + c) % 3][k];
  return key;
}

}  // namespace

CasterMeshes caster_meshes(const Scene& scene) {
  CasterMeshes c;
  // Coincident triangles (two copies of a box, a doubled face) occlude once: a second copy would
  // add its hard count and its silhouette's coverage again, doubling the penumbra.
  std::unordered_set<TriangleKey, TriangleKeyHash> seen;
  for (const Mesh& original : scene.meshes) {
    if (!original.casts_shadows || original.triangles.empty()) continue;
    std::vector<Triangle> kept;
    for (const Triangle& t : original.triangles) {
      const bool valid = t.v[0] < original.positions.size() && t.v[1] < original.positions.size() &&
                         t.v[2] < original.positions.size();
      if (!valid || seen.insert(triangle_key(original, t)).second) kept.push_back(t);
    }
    if (kept.empty()) {
      c.duplicate_faces += original.triangles.size();
      continue;
    }
    const Mesh* source = &original;
    if (kept.size() < original.triangles.size()) {
      c.duplicate_faces += original.triangles.size() - kept.size();
      auto copy = std::make_shared<Mesh>(original);
      copy->triangles = std::move(kept);
      source = copy.get();
      c.owned.push_back(std::move(copy));
    }
    const Mesh& mesh = *source;
    MeshEdges edges = build_mesh_edges(mesh);
    const Mesh* used = &mesh;
    if (edges.inconsistent_edges > 0) {
      Reorientation r;
      auto fixed = std::make_shared<const Mesh>(reorient(mesh, edges, &r));
      if (r.changed()) {
        edges = build_mesh_edges(*fixed);
        used = fixed.get();
        c.flipped_faces += r.flipped;
        c.owned.push_back(std::move(fixed));
      }
    }
    c.solid.push_back(solid_for_wedges(*used, edges));
    c.bounds.push_back(used->bounds());
    c.meshes.push_back(used);
    c.edges.push_back(std::move(edges));
  }
  return c;
}

Casters make_casters(const CasterMeshes& meshes, const Vec3& centre) {
  Casters c;
  c.reoriented = meshes.owned;
  for (size_t k = 0; k < meshes.meshes.size(); ++k) {
    const Mesh& mesh = *meshes.meshes[k];
    const MeshEdges& edges = meshes.edges[k];
    const bool solid = meshes.solid[k] != 0;
    // The light centre inside a solid, or on its surface (the tie rule of docs/architecture.md:
    // a face through the light point blocks nothing): its light-facing faces miss the segments'
    // last crossing, so every face crossed counts, one layer (what shadow_volume counts).
    const Bounds3& box = meshes.bounds[k];
    const bool in_box = glm::all(glm::greaterThanEqual(centre, box.lo)) &&
                        glm::all(glm::lessThanEqual(centre, box.hi));
    const bool centre_inside = solid && in_box &&
                               (point_on_surface(mesh, edges, DVec3(centre)) ||
                                std::abs(winding_number(mesh, edges, DVec3(centre))) > 0.5);
    std::vector<std::unique_ptr<Mesh>> parts;
    if (!centre_inside) parts = facing_patches(mesh, edges, centre, solid);
    if (parts.empty()) {  // inside, on, or a sheet seen edge-on: the whole mesh, every crossing
      c.layers.push_back(1);
      c.meshes.push_back(&mesh);
      c.edges.push_back(edges);
      continue;
    }
    for (auto& part : parts) {
      c.layers.push_back(1);  // an open sheet: its count is the number of its faces crossed
      c.edges.push_back(build_mesh_edges(*part));
      c.meshes.push_back(part.get());
      c.owned.push_back(std::move(part));
    }
  }
  return c;
}

Casters make_casters(const Scene& scene, const Vec3& centre) {
  return make_casters(caster_meshes(scene), centre);
}

std::vector<WedgeEdge> silhouette_edges(const Casters& casters, const Vec3& centre) {
  std::vector<WedgeEdge> sil;
  for (size_t m = 0; m < casters.meshes.size(); ++m) {
    const Mesh& mesh = *casters.meshes[m];
    for (const SilhouetteEdge& s : point_silhouette(mesh, casters.edges[m], centre))
      sil.push_back({DVec3(mesh.positions[s.from]), DVec3(mesh.positions[s.to]),
                     static_cast<double>(s.multiplicity) / casters.layers[m],
                     static_cast<uint32_t>(m)});
  }
  return sil;
}

namespace {

Image<int32_t> counts_of(const ShadowContext& ctx, const std::vector<CountCaster>& casters,
                         const Vec3& point, const ShadowVolumePixels* pixels = nullptr) {
  ShadowVolumePixels own;
  if (!pixels) own = shadow_volume_pixels(ctx.scene.camera, ctx.gbuffer, ctx.receivers);
  return shadow_volume_counts(casters, pixels ? *pixels : own, ctx.gbuffer, ctx.receivers, point);
}

}  // namespace

Image<int32_t> hard_counts(const ShadowContext& ctx, const std::vector<CountCaster>& casters,
                           const Vec3& point, const ShadowVolumePixels* pixels) {
  return counts_of(ctx, casters, point, pixels);
}

Image<float> layered_counts(const ShadowContext& ctx, const Casters& casters, const Vec3& point,
                            const ShadowVolumePixels* pixels) {
  const GBuffer& g = ctx.gbuffer;
  Image<float> out(g.width, g.height, 0.0f);
  for (int l : {1, 2}) {
    bool any = false, all = true;
    for (int layers : casters.layers) {
      any |= layers == l;
      all &= layers == l;
    }
    if (!any) continue;
    Image<int32_t> counts;
    if (all && casters.owned.empty()) {
      counts = pixels ? shadow_volume_counts(ctx.scene, *pixels, g, ctx.receivers, point)
                      : shadow_volume_counts(ctx.scene, ctx.scene.camera, g, ctx.receivers, point);
    } else {
      std::vector<CountCaster> part;
      for (size_t m = 0; m < casters.meshes.size(); ++m)
        if (casters.layers[m] == l) part.push_back({casters.meshes[m], &casters.edges[m]});
      counts = counts_of(ctx, part, point, pixels);
    }
    for (size_t i = 0; i < counts.size(); ++i)
      out[i] += static_cast<float>(counts[i]) / static_cast<float>(l);
  }
  return out;
}

GroupCounts group_counts(const ShadowContext& ctx, const Casters& casters, const Vec3& point,
                         const ShadowVolumePixels* pixels_in) {
  const size_t n = ctx.gbuffer.pixel_count();
  std::vector<std::vector<std::pair<uint32_t, float>>> per_group(casters.meshes.size());
  std::vector<uint32_t> per_pixel(n + 1, 0);
  // One pixel setup for all groups (at 2048² it costs more than a small group's own count).
  ShadowVolumePixels own;
  if (!pixels_in) own = shadow_volume_pixels(ctx.scene.camera, ctx.gbuffer, ctx.receivers);
  const ShadowVolumePixels& pixels = pixels_in ? *pixels_in : own;
  for (size_t m = 0; m < casters.meshes.size(); ++m) {
    const Image<int32_t> counts =
        counts_of(ctx, {{casters.meshes[m], &casters.edges[m]}}, point, &pixels);
    for (size_t i = 0; i < n; ++i) {
      if (counts[i] == 0) continue;
      per_group[m].emplace_back(static_cast<uint32_t>(i),
                                static_cast<float>(counts[i]) / casters.layers[m]);
      ++per_pixel[i + 1];
    }
  }
  GroupCounts gc;
  gc.begin.assign(n + 1, 0);
  for (size_t i = 0; i < n; ++i) gc.begin[i + 1] = gc.begin[i] + per_pixel[i + 1];
  gc.group.resize(gc.begin[n]);
  gc.value.resize(gc.begin[n]);
  std::vector<uint32_t> fill(gc.begin.begin(), gc.begin.end() - 1);
  for (size_t m = 0; m < per_group.size(); ++m) {  // group order: entries sorted by group
    for (const auto& [i, v] : per_group[m]) {
      gc.group[fill[i]] = static_cast<uint32_t>(m);
      gc.value[fill[i]++] = v;
    }
  }
  return gc;
}

std::vector<std::vector<uint32_t>> bin_hulls(
    const ShadowContext& ctx, const PixelSetup& setup, const std::vector<std::vector<DVec2>>& hulls,
    const std::function<bool(uint32_t item, size_t tile)>& may_hold) {
  const GBuffer& g = ctx.gbuffer;
  std::vector<DVec2> yrange(hulls.size(), DVec2(kInfinity, -kInfinity));
  for (size_t k = 0; k < hulls.size(); ++k)
    for (const DVec2& p : hulls[k])
      yrange[k] = DVec2(std::min(yrange[k].x, p.y), std::max(yrange[k].y, p.y));
  // One tile row per task (deterministic order: item index).
  const int tiles_x = (g.width + kTile - 1) / kTile, tiles_y = (g.height + kTile - 1) / kTile;
  std::vector<std::vector<uint32_t>> bins(static_cast<size_t>(tiles_x) * tiles_y);
  const double margin = setup.margin;
  parallel_rows(tiles_y, [&](int ty) {
    const double y0 = ty * kTile + 0.5 - margin,
                 y1 = std::min(g.height, (ty + 1) * kTile) - 0.5 + margin;
    for (uint32_t k = 0; k < hulls.size(); ++k) {
      if (yrange[k].y < y0 || yrange[k].x > y1) continue;
      double x0 = 0.0, x1 = 0.0;
      if (!hull_row_span(hulls[k], y0, y1, x0, x1)) continue;
      const double ta = std::floor((x0 - margin - 0.5) / kTile),
                   tb = std::floor((x1 + margin - 0.5) / kTile);
      if (tb < 0.0 || ta > tiles_x - 1.0) continue;
      const int a = static_cast<int>(std::max(0.0, ta)),
                b = static_cast<int>(std::min(tiles_x - 1.0, tb));
      for (int tx = a; tx <= b; ++tx) {
        const size_t t = static_cast<size_t>(ty) * tiles_x + tx;
        if (may_hold(k, t)) bins[t].push_back(k);
      }
    }
  });
  return bins;
}

BinnedWedges build_and_bin(const ShadowContext& ctx, const PixelSetup& setup,
                           const std::vector<WedgeEdge>& sil, const WedgeLight& light,
                           WedgeConstruction construction) {
  const GBuffer& g = ctx.gbuffer;
  const double scale = std::max(1.0, static_cast<double>(ctx.scene.bounds().diagonal()));
  BinnedWedges bw;
  bw.wedges.resize(sil.size());
  bw.group.resize(sil.size());
  std::vector<std::vector<DVec2>> hulls(sil.size());
  parallel_chunks(sil.size(), 64, [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) {
      const Wedge& w = bw.wedges[k] =
          build_wedge(sil[k].from, sil[k].to, sil[k].weight, light, construction, scale);
      bw.group[k] = sil[k].group;
      hulls[k] = wedge_screen_hull(setup.screen, w.top0, w.top1, light.hull);
    }
  });

  for (const Wedge& w : bw.wedges) bw.degenerate += w.degenerate;

  bw.tiles_x = (g.width + kTile - 1) / kTile;
  bw.tiles_y = (g.height + kTile - 1) / kTile;
  bw.bins = bin_hulls(ctx, setup, hulls, [&](uint32_t k, size_t t) {
    return bw.wedges[k].may_hold_box(setup.tile_lo[t], setup.tile_hi[t]);
  });
  return bw;
}

PixelLight::PixelLight(const Light& light, const LightFrame& fixed_frame, bool per_pixel_frame,
                       const Vec3& origin)
    : p_(origin) {
  const LightFrame f = per_pixel_frame ? light_frame(light, origin) : fixed_frame;
  if (!make_light_projection(p_, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), lp_)) return;
  valid_ = true;
  round_ = f.round;
  // τ: orientation of light uv as seen from p; with it the sign of (c, a, b) in uv tells the
  // inner half (−) from the outer half (+) [wedges/coverage.hpp].
  tau_ = glm::dot(lp_.to_w, glm::cross(DVec3(f.edge_u), DVec3(f.edge_v))) > 0.0 ? 1.0 : -1.0;
  inv_area_ = 1.0 / f.uv_area();
}

bool PixelLight::clip(const Wedge& w, DVec2& a, DVec2& b) const {
  if (!clip_edge_to_light_square(lp_.homogeneous(w.e0), lp_.homogeneous(w.e1), a, b)) return false;
  return !round_ || clip_edge_to_light_disk(a, b);
}

}  // namespace penumbra::wedge_pass
