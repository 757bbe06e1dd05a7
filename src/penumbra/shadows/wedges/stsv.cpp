#include "penumbra/shadows/wedges/stsv.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/screen.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::stsv {

OptionSpec alpha_option() {
  return {"alpha",
          OptionType::choice,
          "stsv",
          "alpha-textured (perforated) occluders: stsv (soft textured shadow volumes, Forest 2008 "
          "ch. 5: per light sample, the alpha texel the segment crosses) or opaque (every "
          "alpha-textured triangle solid)",
          {"stsv", "opaque"}};
}

bool uses_stsv(const MethodOptions& options) {
  return options.get_choice("alpha") == "stsv";
}

namespace {

/// Adds plane (m, a) to the side unless it is there already or the side is full (a plane left out
/// only loosens the volume).
void add_plane(Wedge& w, const DVec3& m, const DVec3& a) {
  const double d = glm::dot(m, a);
  for (int i = 0; i < w.plane_count; ++i)
    if (glm::dot(w.planes[i].n, m) > 1.0 - 1e-12 && std::abs(w.planes[i].d - d) <= w.tolerance)
      return;
  if (w.plane_count < kMaxWedgePlanes) w.planes[w.plane_count++] = {m, d};
}

/// One side's volume: the planes through each edge of `top` (and the plane of `top`, the front cap)
/// that keep the opposite vertex inside and every light point of `part` outside. Each such plane
/// holds the region conv{top} + cone{top_i − x}, x in hull(part), that holds the side's shadow.
void build_side(Wedge& w, const DVec3 top[3], const std::vector<DVec3>& part) {
  auto valid = [&](const DVec3& m, const DVec3& a, const DVec3& o) {
    if (glm::dot(m, o - a) < -w.tolerance) return false;
    for (const DVec3& y : part)
      if (glm::dot(m, y - a) > w.tolerance) return false;
    return true;
  };
  // Outer quads of the edges' penumbra wedges [§5.1.2, fig. 5.1 left]: their planes pass through
  // the edge and touch the light; any such plane with the light outside bounds the shadow.
  for (int i = 0; i < 3; ++i) {
    const DVec3 &a = top[i], &b = top[(i + 1) % 3], &o = top[(i + 2) % 3];
    for (const DVec3& x : part) {
      const DVec3 m = glm::cross(b - a, x - a);
      const double len = glm::length(m);
      if (!(len > 1e-12 * glm::length(b - a) * glm::length(x - a))) continue;  // x on the line
      for (const double sign : {1.0, -1.0})
        if (valid(sign * m / len, a, o)) add_plane(w, sign * m / len, a);
    }
  }
  // Front cap: the plane of the (moved) triangle, the light outside.
  const DVec3 n = glm::cross(top[1] - top[0], top[2] - top[0]);
  const double len = glm::length(n);
  if (len > 0.0)
    for (const double sign : {1.0, -1.0})
      if (valid(sign * n / len, top[0], top[0])) add_plane(w, sign * n / len, top[0]);
}

}  // namespace

Volume build_volume(const DVec3 v[3], const std::vector<DVec3>& light_points, const DVec3& centre,
                    double scale) {
  Volume vol;
  const DVec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const double len = glm::length(n);
  if (!(len > 0.0) || light_points.empty()) return vol;
  const DVec3 nu = n / len;
  const double tol = 1e-9 * scale;
  std::vector<double> side(light_points.size());
  bool pos = false, neg = false;
  for (size_t k = 0; k < light_points.size(); ++k) {
    side[k] = glm::dot(nu, light_points[k] - v[0]);
    pos |= side[k] > tol;
    neg |= side[k] < -tol;
  }
  // The light in the triangle's plane: every segment to it meets the plane at its light end,
  // which the tie rule (shadows/method.hpp) never counts.
  if (!pos && !neg) return vol;
  vol.sides[0].tolerance = vol.sides[1].tolerance = tol;
  if (!(pos && neg)) {
    // The paper's case: the front cap t', the vertices moved toward the light centre to the
    // distance of the closest one [§5.1.2]. t' holds the shadow of t because the centre lies in
    // the light's hull (each vertex of t is in t' + cone{t'_i − x}).
    const double sc = glm::dot(nu, centre - v[0]);
    DVec3 top[3] = {v[0], v[1], v[2]};
    double r_min = kInfinity;
    for (int i = 0; i < 3; ++i) r_min = std::min(r_min, glm::length(v[i] - centre));
    if ((pos ? sc > tol : sc < -tol) && r_min > tol)
      for (int i = 0; i < 3; ++i)
        top[i] = centre + (r_min / glm::length(v[i] - centre)) * (v[i] - centre);
    build_side(vol.sides[vol.side_count++], top, light_points);
    return vol;
  }
  // The light crosses the plane: both sides of the triangle cast [§5.5], each from the part of
  // the light on its side (the hull points there and the crossings of the segments between them).
  for (const double s : {1.0, -1.0}) {
    std::vector<DVec3> part;
    for (size_t k = 0; k < light_points.size(); ++k)
      if (s * side[k] >= -tol) part.push_back(light_points[k]);
    for (size_t j = 0; j < light_points.size(); ++j)
      for (size_t k = j + 1; k < light_points.size(); ++k)
        if ((side[j] > tol && side[k] < -tol) || (side[j] < -tol && side[k] > tol))
          part.push_back(light_points[j] +
                         (side[j] / (side[j] - side[k])) * (light_points[k] - light_points[j]));
    build_side(vol.sides[vol.side_count++], v, part);
  }
  return vol;
}

Footprint classify(const Texture& alpha, const Vec2 uv[3]) {
  if (alpha.width <= 0 || alpha.height <= 0 || alpha.texels.empty()) return Footprint::opaque;
  // The texels a lookup inside the triangle can reach: its uv box, widened by float rounding of
  // the interpolated uv, with the repeat wrap of Texture::texel_index.
  const float eps = 1e-4f;
  float lo[2] = {kInfinity, kInfinity}, hi[2] = {-kInfinity, -kInfinity};
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], uv[i][a] - eps);
      hi[a] = std::max(hi[a], uv[i][a] + eps);
    }
  const int size[2] = {alpha.width, alpha.height};
  int64_t first[2], count[2];
  for (int a = 0; a < 2; ++a) {
    if (!(hi[a] - lo[a] < 1.0f)) {
      first[a] = 0, count[a] = size[a];
      continue;
    }
    first[a] = static_cast<int64_t>(std::floor(static_cast<double>(lo[a]) * size[a]));
    const int64_t last = static_cast<int64_t>(std::floor(static_cast<double>(hi[a]) * size[a]));
    count[a] = std::min<int64_t>(size[a], last - first[a] + 1);
  }
  if (count[0] * count[1] > (int64_t{1} << 22)) return Footprint::perforated;  // not scanned
  bool any_opaque = false, any_hole = false;
  for (int64_t y = 0; y < count[1]; ++y) {
    const int ty = static_cast<int>(((first[1] + y) % size[1] + size[1]) % size[1]);
    for (int64_t x = 0; x < count[0]; ++x) {
      const int tx = static_cast<int>(((first[0] + x) % size[0] + size[0]) % size[0]);
      (alpha.channel(tx, ty, 0) < kAlphaCutoff ? any_hole : any_opaque) = true;
      if (any_hole && any_opaque) return Footprint::perforated;
    }
  }
  return any_hole ? Footprint::holes : Footprint::opaque;
}

Perforated take_perforated(const Scene& scene, wedge_pass::CasterMeshes& c) {
  Perforated out;
  std::vector<std::shared_ptr<Mesh>> parts;
  size_t kept = 0;
  for (size_t m = 0; m < c.meshes.size(); ++m) {
    const Mesh& mesh = *c.meshes[m];
    const Material& mat = scene.material_of(mesh);
    bool keep = true;
    if (mat.alpha_texture >= 0 && mat.alpha_texture < static_cast<int>(scene.textures.size())) {
      const Texture& tex = scene.textures[mat.alpha_texture];
      std::vector<Triangle> opaque;
      std::vector<STriangle> perforated;
      size_t holes = 0;
      for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec2 uv[3] = {mesh.uv_at(t, 0.0f, 0.0f), mesh.uv_at(t, 1.0f, 0.0f),
                            mesh.uv_at(t, 0.0f, 1.0f)};
        const Footprint f = classify(tex, uv);
        if (f == Footprint::opaque) {
          opaque.push_back(mesh.triangles[t]);
        } else if (f == Footprint::holes) {
          ++holes;
        } else {
          STriangle s;
          s.v0 = DVec3(mesh.vertex(t, 0));
          s.e1 = DVec3(mesh.vertex(t, 1)) - s.v0;
          s.e2 = DVec3(mesh.vertex(t, 2)) - s.v0;
          const DVec3 n = glm::cross(s.e1, s.e2);
          if (!(glm::dot(n, n) > 0.0)) continue;  // degenerate: blocks nothing
          s.to_triangle = glm::inverse(glm::dmat3(s.e1, s.e2, n));
          s.mesh = &mesh;
          s.prim = static_cast<uint32_t>(t);
          for (int i = 0; i < 3; ++i) s.uv[i] = uv[i];
          s.alpha = &tex;
          s.transmittance = std::max(0.0f, mat.transmittance);
          perforated.push_back(s);
        }
      }
      out.opaque_kept += opaque.size();
      if (opaque.size() < mesh.triangle_count()) {
        keep = false;
        out.holes_dropped += holes;
        out.triangles.insert(out.triangles.end(), perforated.begin(), perforated.end());
        if (!opaque.empty()) {
          auto part = std::make_shared<Mesh>(mesh);
          part->triangles = std::move(opaque);
          parts.push_back(std::move(part));
        }
      }
    }
    if (!keep) continue;
    c.meshes[kept] = c.meshes[m];
    if (kept != m) c.edges[kept] = std::move(c.edges[m]);
    c.solid[kept] = c.solid[m];
    c.bounds[kept] = c.bounds[m];
    ++kept;
  }
  c.meshes.resize(kept);
  c.edges.resize(kept);
  c.solid.resize(kept);
  c.bounds.resize(kept);
  for (std::shared_ptr<Mesh>& part : parts) {
    MeshEdges edges = build_mesh_edges(*part);
    c.solid.push_back(wedge_pass::solid_for_wedges(*part, edges));
    c.bounds.push_back(part->bounds());
    c.meshes.push_back(part.get());
    c.edges.push_back(std::move(edges));
    c.owned.push_back(std::move(part));
  }
  return out;
}

StsvSet build_stsv(const ShadowContext& ctx, const wedge_pass::PixelSetup& setup,
                   Perforated perforated) {
  const GBuffer& g = ctx.gbuffer;
  StsvSet set;
  set.triangles = std::move(perforated.triangles);
  set.opaque_kept = perforated.opaque_kept;
  set.holes_dropped = perforated.holes_dropped;
  set.tiles_x = (g.width + wedge_pass::kTile - 1) / wedge_pass::kTile;
  const int tiles_y = (g.height + wedge_pass::kTile - 1) / wedge_pass::kTile;
  if (set.triangles.empty() || !setup.any_active) {
    set.bins.assign(static_cast<size_t>(set.tiles_x) * tiles_y, {});
    return set;
  }
  std::vector<DVec3> light_points = wedge_pass::light_hull_points(ctx.light);
  const DVec3 centre(hard_shadow_point(ctx.light));
  if (light_points.empty()) light_points.push_back(centre);  // a point light
  const double scale = std::max(1.0, static_cast<double>(ctx.scene.bounds().diagonal()));
  set.volumes.resize(set.triangles.size());
  std::vector<std::vector<DVec2>> hulls(set.triangles.size());
  parallel_chunks(set.triangles.size(), 64, [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) {
      const STriangle& t = set.triangles[k];
      const DVec3 v[3] = {t.v0, t.v0 + t.e1, t.v0 + t.e2};
      set.volumes[k] = build_volume(v, light_points, centre, scale);
      // The screen bound of the region the triangle can shadow (conv{v} + cone{v_i − x_k}, for
      // either side): the same generators as a wedge's top edge (wedges/screen.hpp).
      if (set.volumes[k].side_count > 0)
        hulls[k] = extrusion_screen_hull(setup.screen, v, light_points);
    }
  });
  for (const Volume& v : set.volumes) set.two_sided += v.side_count == 2;
  set.bins = wedge_pass::bin_hulls(ctx, setup, hulls, [&](uint32_t k, size_t t) {
    return set.volumes[k].may_hold_box(setup.tile_lo[t], setup.tile_hi[t]);
  });
  return set;
}

Summary summarize(const StsvSet& set, const StsvStats& stats, double ms) {
  Summary s;
  s.ran = true;
  s.triangles = set.triangles.size();
  s.two_sided = set.two_sided;
  s.opaque_kept = set.opaque_kept;
  s.holes_dropped = set.holes_dropped;
  for (const auto& bin : set.bins) s.bin_entries += bin.size();
  s.stats = stats;
  s.ms = ms;
  return s;
}

void report(const Summary& s, Visibility& out) {
  if (!s.ran) return;
  out.times.add("stsv", s.ms);
  Counters& k = out.counters;
  k["stsv_triangles"] = static_cast<double>(s.triangles);
  k["stsv_two_sided_volumes"] = static_cast<double>(s.two_sided);
  k["stsv_alpha_opaque_triangles"] = static_cast<double>(s.opaque_kept);
  k["stsv_alpha_hole_triangles"] = static_cast<double>(s.holes_dropped);
  k["stsv_tile_bin_entries"] = static_cast<double>(s.bin_entries);
  k["stsv_volume_tests"] = static_cast<double>(s.stats.volume_tests);
  k["stsv_pixel_triangle_pairs"] = static_cast<double>(s.stats.pairs);
  k["stsv_sample_lookups"] = static_cast<double>(s.stats.lookups);
  k["stsv_blocked_samples"] = static_cast<double>(s.stats.blocked);
}

}  // namespace penumbra::stsv
