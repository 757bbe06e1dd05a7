// `exact`: the per-point analytic visibility and the ShadowMethod around it.
#include "penumbra/shadows/exact/exact.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

/// Rec. 709 luminance, the collapse of a textured light's RGB visibility to one V_coef that the
/// sampling methods use too (light_weights.hpp).
double luminance(const DVec3& rgb) {
  return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

/// Does the segment origin + t·dir, t ∈ (0, 1], cross the triangle (a, b, c)? Möller–Trumbore in
/// double, edges inclusive. A segment lying in the triangle's plane crosses it in a set of
/// measure zero and is not counted.
bool segment_hits_triangle(const DVec3& origin, const DVec3& dir, const DVec3& a, const DVec3& b,
                           const DVec3& c) {
  const DVec3 e1 = b - a, e2 = c - a;
  const DVec3 pvec = glm::cross(dir, e2);
  const double det = glm::dot(e1, pvec);
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const DVec3 tvec = origin - a;
  const double u = glm::dot(tvec, pvec) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const DVec3 qvec = glm::cross(tvec, e1);
  const double v = glm::dot(dir, qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = glm::dot(e2, qvec) * inv;
  return t > 0.0 && t <= 1.0;
}

/// Slab test of the segment origin + t·dir, t ∈ [0, 1], against a box (conservative: widened by a
/// relative 1e-9 so rounding never drops a touching box).
bool segment_meets_box(const DVec3& origin, const DVec3& dir, const Vec3& lo, const Vec3& hi) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double pad = 1e-9 * (std::abs(static_cast<double>(lo[i])) +
                               std::abs(static_cast<double>(hi[i])) + 1e-30);
    const double l = lo[i] - pad, h = hi[i] + pad;
    if (dir[i] == 0.0) {
      if (origin[i] < l || origin[i] > h) return false;
      continue;
    }
    const double inv = 1.0 / dir[i];
    double a = (l - origin[i]) * inv, b = (h - origin[i]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

/// Does the convex light-uv polygon cover the whole uv square? (Then the receiver is in umbra.)
bool covers_square(const ClipperLib::Path& poly) {
  const ClipperLib::cInt s = static_cast<ClipperLib::cInt>(kUvScale);
  const ClipperLib::IntPoint corners[4] = {{0, 0}, {s, 0}, {s, s}, {0, s}};
  for (const ClipperLib::IntPoint& c : corners)
    if (ClipperLib::PointInPolygon(c, poly) == 0) return false;  // −1 (on the boundary) counts
  return true;
}

ExactPointResult point_light_visibility(const ExactScene& scene, const DVec3& p,
                                        const DVec3& light_pos) {
  ExactPointResult r;
  const DVec3 dir = light_pos - p;
  const auto& occluders = scene.occluders();
  double v = 1.0;
  scene.bvh().traverse(
      [&](const ExactBvh::Node& n) { return segment_meets_box(p, dir, n.lo, n.hi); },
      [&](uint32_t prim) {
        ++r.candidates;
        const ExactOccluder& o = occluders[prim];
        bool hit = false;
        if (!o.cut) {
          hit = segment_hits_triangle(p, dir, o.v[0], o.v[1], o.v[2]);
        } else {
          // The alpha mask decides through the same opaque pieces the area case projects. Pieces
          // of one triangle do not overlap: one crossing at most, even on a shared edge.
          for (uint32_t k = o.piece_first; k < o.piece_first + o.piece_count && !hit; ++k) {
            const ExactPiece& piece = scene.pieces()[k];
            const DVec3* pv = scene.piece_vertices().data() + piece.first;
            for (uint32_t j = 1; j + 1 < piece.count && !hit; ++j)
              hit = segment_hits_triangle(p, dir, pv[0], pv[j], pv[j + 1]);
          }
        }
        if (hit) {
          ++r.polygons;
          v *= o.transmittance;
        }
        return v > 0.0;
      });
  r.visible = v;
  r.visible_rgb = DVec3(v);
  return r;
}

}  // namespace

ExactPointResult exact_visibility(const ExactScene& scene, const ExactLight& light,
                                  const Vec3& receiver) {
  ExactPointResult r;
  const DVec3 p(receiver);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    r.degenerate = true;
    return r;
  }
  const LightFrame frame = light_frame(light.light(), receiver);
  if (light.light().shape == LightShape::point)
    return point_light_visibility(scene, p, DVec3(frame.corner));

  LightProjection proj;
  if (!make_light_projection(p, DVec3(frame.corner), DVec3(frame.edge_u), DVec3(frame.edge_v),
                             proj)) {
    // The receiver lies in the light's plane: every occluder projects onto a line, the visible
    // fraction is undefined. Documented fallback ("light touching geometry"): fully lit.
    r.degenerate = true;
    return r;
  }

  const auto& occluders = scene.occluders();
  ClipperLib::Paths opaque;
  std::vector<SemiPolygon> semi;
  ClipperLib::Path poly;
  bool umbra = false;
  const auto add = [&](const ExactOccluder& o, const DVec3* vertices, int count) {
    if (!project_polygon(proj, vertices, count, poly)) return;
    ++r.polygons;
    if (o.transmittance > 0.0) {
      semi.push_back({poly, o.transmittance});
    } else {
      umbra = umbra || covers_square(poly);
      opaque.push_back(poly);
    }
  };
  scene.bvh().traverse(
      [&](const ExactBvh::Node& n) { return box_meets_pyramid(proj, n.lo, n.hi); },
      [&](uint32_t prim) {
        ++r.candidates;
        const ExactOccluder& o = occluders[prim];
        if (!o.cut) {
          add(o, o.v, 3);
        } else {
          for (uint32_t k = o.piece_first; k < o.piece_first + o.piece_count; ++k) {
            const ExactPiece& piece = scene.pieces()[k];
            add(o, scene.piece_vertices().data() + piece.first, static_cast<int>(piece.count));
          }
        }
        return !umbra;  // one opaque polygon hides the whole light: done
      });
  if (umbra) {
    r.visible = 0.0;
    r.visible_rgb = DVec3(0.0);
    return r;
  }
  if (opaque.empty() && semi.empty()) return r;

  const LightOutline& outline = light.outline();
  const std::vector<LightRegion> regions = visible_regions(outline, opaque, semi);
  double visible_area = 0.0;
  for (const LightRegion& region : regions)
    visible_area += region.weight * paths_area(region.paths);
  double v = visible_area / outline.area;
  v = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0;
  r.visible = v;
  r.visible_rgb = DVec3(v);

  if (light.textured()) {
    // Per channel Σ_texels weight · area(texel ∩ visible) / Σ_texels weight · area(texel ∩ light).
    DVec3 seen(0.0);
    for (const LightRegion& region : regions)
      seen += region.weight * texel_weighted_area(region.paths, light.texture_width(),
                                                  light.texture_height(), light.texel_weight());
    const DVec3& total = light.total_weight();
    for (int c = 0; c < 3; ++c) {
      const double f = total[c] > 0.0 ? seen[c] / total[c] : 1.0;
      r.visible_rgb[c] = std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;
    }
    const double lum_total = luminance(total);
    const double f = lum_total > 0.0 ? luminance(seen) / lum_total : 1.0;
    r.visible = std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;
  }
  return r;
}

double exact_visible_fraction(const ExactScene& scene, const Light& light, Vec3 receiver,
                              int disk_segments) {
  const ExactLight exact_light(scene.scene(), light, disk_segments);
  return exact_visibility(scene, exact_light, receiver).visible;
}

namespace {

class ExactMethod final : public ShadowMethod {
 public:
  explicit ExactMethod(const ExactOptions& options) : options_(options) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);

    ScopedStage bvh_stage(vis.times, "bvh");
    const ExactScene scene(ctx.scene, options_.leaf_size);
    const ExactLight light(ctx.scene, ctx.light, options_.disk_segments);
    bvh_stage.stop();
    if (light.textured()) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));

    // Per-row statistics, summed in row order afterwards: the counters never depend on threads.
    struct RowStats {
      double pixels = 0, candidates = 0, candidates_max = 0, polygons = 0;
      double lit = 0, umbra = 0, penumbra = 0, degenerate = 0;
    };
    std::vector<RowStats> rows(static_cast<size_t>(std::max(0, g.height)));
    {
      ScopedStage stage(vis.times, "visibility");
      Progress progress("exact", static_cast<size_t>(g.height));
      parallel_rows(g.height, [&](int y) {
        RowStats& s = rows[static_cast<size_t>(y)];
        for (int x = 0; x < g.width; ++x) {
          const size_t i = static_cast<size_t>(y) * g.width + x;
          if (ctx.receivers[i] != kActive) continue;
          const ExactPointResult r = exact_visibility(scene, light, g.shadow_origin(i));
          vis.lit[i] = static_cast<float>(r.visible);
          if (vis.lit_rgb) (*vis.lit_rgb)[i] = Vec3(r.visible_rgb);
          s.pixels += 1;
          s.candidates += r.candidates;
          s.candidates_max = std::max(s.candidates_max, static_cast<double>(r.candidates));
          s.polygons += r.polygons;
          s.degenerate += r.degenerate ? 1 : 0;
          if (r.visible >= 1.0 - 1e-9) {
            s.lit += 1;
          } else if (r.visible <= 1e-9) {
            s.umbra += 1;
          } else {
            s.penumbra += 1;
          }
        }
        progress.advance();
      });
    }

    RowStats t;
    for (const RowStats& s : rows) {
      t.pixels += s.pixels;
      t.candidates += s.candidates;
      t.candidates_max = std::max(t.candidates_max, s.candidates_max);
      t.polygons += s.polygons;
      t.lit += s.lit;
      t.umbra += s.umbra;
      t.penumbra += s.penumbra;
      t.degenerate += s.degenerate;
    }
    Counters& c = vis.counters;
    c["pixels"] = t.pixels;
    c["candidate_triangles"] = t.candidates;
    c["candidates_per_pixel"] = t.pixels > 0 ? t.candidates / t.pixels : 0.0;
    c["candidates_max"] = t.candidates_max;
    c["projected_polygons"] = t.polygons;
    c["pixels_lit"] = t.lit;
    c["pixels_umbra"] = t.umbra;
    c["pixels_penumbra"] = t.penumbra;
    c["degenerate_fallbacks"] = t.degenerate;
    c["occluder_triangles"] = static_cast<double>(scene.occluders().size());
    c["alpha_pieces"] = static_cast<double>(scene.pieces().size());
    c["bvh_nodes"] = static_cast<double>(scene.bvh().nodes().size());
    return vis;
  }

 private:
  ExactOptions options_;
};

}  // namespace

std::unique_ptr<ShadowMethod> make_exact_method(const ExactOptions& options) {
  return std::make_unique<ExactMethod>(options);
}

void register_exact(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "exact";
  info.summary =
      "analytic visible fraction per pixel: occluders projected onto the light by homogeneous "
      "clipping, union area with exact integer polygon booleans (no samples)";
  info.reference =
      "Penumbra's analytic reference: V_coef [Forest 2008 eq. 2.10], semi-opaque occluders "
      "[Forest 2008 §4.3.3] (docs/references.md)";
  info.sample_exact = false;  // analytic: the limit raytrace converges to, not sample-equal
  info.options = {
      {"disk_segments",
       OptionType::integer,
       "256",
       "sides of the equal-area polygon standing in for a round light (|error in V| <= 0.128 "
       "(pi/N)^2)",
       {},
       16,
       1 << 20},
      {"leaf_size",
       OptionType::integer,
       "4",
       "triangles per leaf of the reference's own BVH",
       {},
       1,
       64},
  };
  info.create = [](const MethodOptions& o) {
    ExactOptions options;
    options.disk_segments = o.get_int("disk_segments");
    options.leaf_size = o.get_int("leaf_size");
    return make_exact_method(options);
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
