#include "penumbra/shadows/gears/assign.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/core/stats.hpp"

namespace penumbra::gears {

namespace {

using DVec4 = glm::dvec4;

/// Inclusive cell range of a footprint; empty when x0 > x1.
struct CellRect {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
  uint64_t area() const { return empty() ? 0 : uint64_t(x1 - x0 + 1) * uint64_t(y1 - y0 + 1); }
};

CellRect intersect(const CellRect& a, const CellRect& b) {
  return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

/// The triangle polygon clipped to z ≤ z_cut (Sutherland–Hodgman, one plane): ≤ 4 vertices.
int clip_far(const DVec3 tri[3], double z_cut, DVec3 out[4]) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const DVec3& a = tri[i];
    const DVec3& b = tri[(i + 1) % 3];
    const bool ain = a.z <= z_cut, bin = b.z <= z_cut;
    if (ain) out[n++] = a;
    if (ain != bin) {
      const double t = (z_cut - a.z) / (b.z - a.z);
      out[n++] = a + t * (b - a);
      out[n - 1].z = z_cut;
    }
  }
  return n;
}

/// 2D AABB, in cells, of the shadow volume of `tri` truncated at depth z_t: the polygon's vertices
/// and their extrusions through every light corner to z_t, projected by C [Wang 2014 §3.1 (3.3)].
/// Conservative: for a fixed blocking point H the extrusions of the light through H are a central
/// projection of a convex set, and C's projection is affine on the plane z = z_t, so the projected
/// volume lies in the convex hull of these points.
CellRect footprint(const GridCamera& cam, const DVec3 tri[3], double z_t) {
  DVec3 poly[4];
  const int n = clip_far(tri, z_t, poly);
  if (n == 0) return {};
  const DVec3 eye(cam.eye);
  const DVec2 lo_grid(cam.grid_lo), scale(cam.cell_scale);
  const double plane = cam.plane_z;
  DVec2 lo(1e300), hi(-1e300);
  auto add_scaled = [&](double qx, double qy, double s) {  // s: C's scale at the point's depth
    const DVec2 g((eye.x + (qx - eye.x) * s - lo_grid.x) * scale.x,
                  (eye.y + (qy - eye.y) * s - lo_grid.y) * scale.y);
    lo = glm::min(lo, g);
    hi = glm::max(hi, g);
  };
  auto add = [&](const DVec3& q) { add_scaled(q.x, q.y, (plane - eye.z) / (q.z - eye.z)); };
  const bool flat = std::all_of(cam.light_corners.begin(), cam.light_corners.end(),
                                [](const Vec3& l) { return l.z == 0.0f; });
  if (flat) {
    // Light corners on z = 0 (rectangles, disks, points): the extrusions of a vertex share one
    // ratio z_t / v.z, and all lie on z = z_t, where C has one scale.
    const double s_t = (plane - eye.z) / (z_t - eye.z);
    for (int i = 0; i < n; ++i) {
      add(poly[i]);
      const double r = z_t / poly[i].z;
      for (const Vec3& lf : cam.light_corners)
        add_scaled(lf.x + (poly[i].x - lf.x) * r, lf.y + (poly[i].y - lf.y) * r, s_t);
    }
  } else {
    for (int i = 0; i < n; ++i) {
      add(poly[i]);
      for (const Vec3& lf : cam.light_corners) {
        const DVec3 l(lf);
        add(l + (poly[i] - l) * ((z_t - l.z) / (poly[i].z - l.z)));
      }
    }
  }
  // Float rounding of the sample projections is far below a thousandth of a cell.
  constexpr double kMargin = 1e-3;
  lo -= kMargin;
  hi += kMargin;
  if (!(hi.x >= 0.0) || !(hi.y >= 0.0) || !(lo.x < cam.res_x) || !(lo.y < cam.res_y)) return {};
  CellRect r;
  r.x0 = static_cast<int>(std::floor(std::max(lo.x, 0.0)));
  r.y0 = static_cast<int>(std::floor(std::max(lo.y, 0.0)));
  r.x1 = static_cast<int>(std::floor(std::min(hi.x, cam.res_x - 1.0)));
  r.y1 = static_cast<int>(std::floor(std::min(hi.y, cam.res_y - 1.0)));
  return r;
}

/// A sphere light seen by the cells, for triangles that reach its depth slab (their extrusion is
/// unbounded). Such a triangle T can block a sample P in the ball (q, ρ) from a light point X in
/// the light's ball (c, r) only if some H = (1 − s)·P + s·X lies in T; H is within
/// (1 − s)·ρ + s·r ≤ max(ρ, r) of the segment q–c, so T's bounding sphere (m, σ) must reach the
/// capsule of radius max(ρ, r) around that segment. Distances in world units: light-space x and
/// y are in units of the light's diameter, z in world units.
struct SlabCull {
  bool on = false;
  double scale_xy = 1.0;  // world units per light-space x or y unit
  DVec3 centre{0.0};      // the light's centre (scaled)
  double radius = 0.0;
  std::vector<DVec4> cells;  // per cell: the samples' bounding sphere (scaled centre, radius)
  // Blocks of cells with samples, each with a sphere around its cells' spheres: one test rejects
  // a block (the capsule of a bigger sample ball contains the smaller ones' hulls).
  struct Block {
    DVec4 sphere;
    std::vector<int> cells;
  };
  std::vector<Block> blocks;

  DVec3 scaled(const DVec3& q) const { return DVec3(q.x * scale_xy, q.y * scale_xy, q.z); }
  bool may_block(const DVec4& sphere_tri, const DVec4& samples) const {
    const DVec4& cs = samples;
    const DVec3 q(cs), m(sphere_tri), d = centre - q;
    const double dd = glm::dot(d, d);
    const double s = dd > 0.0 ? std::clamp(glm::dot(m - q, d) / dd, 0.0, 1.0) : 0.0;
    const double reach = std::max(cs.w, radius) + sphere_tri.w;
    // Inputs are floats: 10⁻⁴ relative slack covers their rounding many times over.
    return glm::length(m - (q + s * d)) <= reach * (1.0 + 1e-4) + 1e-4 * glm::length(q);
  }
  /// Calls f(cell) for each cell with samples that triangle sphere `tri` may shadow.
  template <class F>
  void for_each_cell(const DVec4& tri, F&& f) const {
    for (const Block& b : blocks)
      if (may_block(tri, b.sphere))
        for (int c : b.cells)
          if (may_block(tri, cells[c])) f(c);
  }
};

SlabCull slab_cull(const GridCamera& cam, const PixelCells& cells) {
  SlabCull sc;
  if (cam.light_corners.size() != 8 || !(cam.light_max_z > 0.0f)) return sc;  // not a sphere
  sc.on = true;
  sc.radius = cam.light_max_z;
  sc.scale_xy = 2.0 * cam.light_max_z;
  sc.centre = sc.scaled(DVec3(0.5, 0.5, 0.0));
  sc.cells.resize(cells.max_z.size());
  for (size_t c = 0; c < sc.cells.size(); ++c) {
    if (!(cells.max_z[c] > -kInfinity)) {
      sc.cells[c] = DVec4(0.0, 0.0, 0.0, -1.0);
      continue;
    }
    const DVec3 lo = sc.scaled(DVec3(cells.box_lo[c])), hi = sc.scaled(DVec3(cells.box_hi[c]));
    sc.cells[c] = DVec4(0.5 * (lo + hi), 0.5 * glm::length(hi - lo));
  }
  constexpr int kBlock = 16;  // cells per block side
  for (int by = 0; by < cam.res_y; by += kBlock)
    for (int bx = 0; bx < cam.res_x; bx += kBlock) {
      SlabCull::Block b;
      DVec3 lo(1e300), hi(-1e300);
      for (int y = by; y < std::min(by + kBlock, cam.res_y); ++y)
        for (int x = bx; x < std::min(bx + kBlock, cam.res_x); ++x) {
          const DVec4& cs = sc.cells[y * cam.res_x + x];
          if (!(cs.w >= 0.0)) continue;
          b.cells.push_back(y * cam.res_x + x);
          lo = glm::min(lo, DVec3(cs) - cs.w), hi = glm::max(hi, DVec3(cs) + cs.w);
        }
      if (b.cells.empty()) continue;
      const DVec3 mid = 0.5 * (lo + hi);
      double radius = 0.0;
      for (int c : b.cells)
        radius = std::max(radius, glm::length(DVec3(sc.cells[c]) - mid) + sc.cells[c].w);
      b.sphere = DVec4(mid, radius * (1.0 + 1e-9));
      sc.blocks.push_back(std::move(b));
    }
  return sc;
}

/// Pass 1's counts, AssignStats' fields of the same names.
struct PassCounts {
  uint64_t behind = 0, beyond = 0, straddle = 0, no_retraction = 0, aabb_cells = 0;
};

/// One side's assignment: its inputs, and pass 1's result per triangle, which pass 2 reads.
struct Assignment {
  const GridCamera& cam;
  const TriangleSoup& soup;
  const PixelCells& cells;
  const AssignOptions& options;
  double sgn;         // +1, or −1: the soup's depths mirrored
  double straddle_z;  // a triangle whose nearest depth is at most this reaches the light's
  SlabCull slab;      // sphere lights: triangles in the light's depth slab, tested per cell
  // Per triangle: its cell rectangle and nearest depth; sphere lights' slab triangles: their
  // bounding sphere (w < 0: not one) and the cells found for them.
  std::vector<CellRect> rects;
  std::vector<float> zmins;
  std::vector<DVec4> slab_sphere;
  std::vector<std::vector<uint32_t>> slab_cells;

  Assignment(const GridCamera& c, const TriangleSoup& s, int side, const PixelCells& pc,
             const AssignOptions& o)
      : cam(c),
        soup(s),
        cells(pc),
        options(o),
        sgn(side < 0 ? -1.0 : 1.0),
        straddle_z(c.light_max_z + 1e-6 * std::max(1.0, std::abs(static_cast<double>(c.far_z)))),
        slab(slab_cull(c, pc)),
        rects(s.size()),
        zmins(s.size()),
        slab_sphere(slab.on ? s.size() : 0, DVec4(0.0, 0.0, 0.0, -1.0)),
        slab_cells(slab.on ? s.size() : 0) {}

  /// A blocker can be as deep as the deepest light point (a sphere reaches behind samples within
  /// its depth slab): the depth cut compares against max(deepest sample, light_max_z).
  bool cell_ok(int c, float zmin) const {
    const float mz = cells.max_z[c];
    if (!(mz > -kInfinity)) return false;  // no samples
    return !options.cell_depth_cull || std::max(mz, cam.light_max_z) >= zmin;
  }
  bool slab_triangle(size_t t) const { return slab.on && slab_sphere[t].w >= 0.0; }

  /// Pass 1 for triangle t: its cells and nearest depth, and its share of the counts.
  void count_triangle(size_t t, PassCounts& n) {
    DVec3 tri[3];
    for (int c = 0; c < 3; ++c) tri[c] = DVec3(soup.x[c][t], soup.y[c][t], sgn * soup.z[c][t]);
    CellRect r = triangle_rect(t, tri, n);
    if (slab_triangle(t)) {
      slab.for_each_cell(slab_sphere[t], [&](int c) {
        if (cell_ok(c, zmins[t])) slab_cells[t].push_back(static_cast<uint32_t>(c));
      });
      n.aabb_cells += slab_cells[t].size();
    } else if (!r.empty()) {
      n.aabb_cells += r.area();
      if (!options.retraction)
        for (int y = r.y0; y <= r.y1; ++y)
          for (int x = r.x0; x <= r.x1; ++x)
            n.no_retraction += cell_ok(y * cam.res_x + x, zmins[t]);
    }
    rects[t] = r;
  }

  /// Triangle t's cell rectangle (`tri`: its vertices, this side's depths): none behind the light
  /// or beyond every sample, the whole grid when it reaches the light's depth, else its
  /// footprint, retracted.
  CellRect triangle_rect(size_t t, const DVec3 tri[3], PassCounts& n) {
    const double zmin = std::min({tri[0].z, tri[1].z, tri[2].z});
    const double zmax = std::max({tri[0].z, tri[1].z, tri[2].z});
    const double far_z = cam.far_z;
    zmins[t] = static_cast<float>(zmin);
    if (zmax < cam.light_min_z) {
      ++n.behind;  // every segment sample→light lies in front of the light plane
      return {};
    }
    if (zmin > far_z) {
      ++n.beyond;
      return {};
    }
    if (zmin <= straddle_z) {
      // Reaches the light's depth: its extrusion is unbounded; the whole grid, for a sphere
      // light only the cells whose capsule it reaches (SlabCull).
      ++n.straddle;
      if (slab.on) {
        DVec3 m(0.0);
        for (int c = 0; c < 3; ++c) m += slab.scaled(tri[c]) / 3.0;
        double radius = 0.0;
        for (int c = 0; c < 3; ++c) radius = std::max(radius, glm::length(slab.scaled(tri[c]) - m));
        slab_sphere[t] = DVec4(m, radius * (1.0 + 1e-6));
      }
      return {0, 0, cam.res_x - 1, cam.res_y - 1};
    }
    const CellRect r = footprint(cam, tri, far_z);
    if (r.empty()) ++n.beyond;
    if (r.empty() || !options.retraction) return r;
    // Retraction [Wang 2014 §3.1]: extrude only to the deepest sample in the touched cells.
    float zr = -kInfinity;
    uint64_t nonempty = 0;
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x) {
        const float mz = cells.max_z[y * cam.res_x + x];
        zr = std::max(zr, mz);
        nonempty += options.cell_depth_cull ? mz >= zmins[t] : mz > -kInfinity;
      }
    n.no_retraction += nonempty;
    return zr < zmin ? CellRect{} : intersect(r, footprint(cam, tri, zr));
  }

  /// Calls f(cell) for each of triangle t's cells (pass 2), in cell order.
  template <class F>
  void for_each_cell(uint32_t t, F&& f) const {
    if (slab_triangle(t)) {
      for (const uint32_t c : slab_cells[t]) f(c);
      return;
    }
    const CellRect& r = rects[t];
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x) {
        const int c = y * cam.res_x + x;
        if (cell_ok(c, zmins[t])) f(static_cast<uint32_t>(c));
      }
  }
};

/// Pass 1 (count): footprint, retraction, cellsN per triangle, in parallel.
PassCounts count_pass(Assignment& a) {
  std::atomic<uint64_t> behind{0}, beyond{0}, straddle{0}, no_retraction{0}, aabb_cells{0};
  parallel_chunks(a.soup.size(), 1024, [&](size_t b, size_t e) {
    PassCounts local;
    for (size_t t = b; t < e; ++t) a.count_triangle(t, local);
    behind += local.behind;
    beyond += local.beyond;
    straddle += local.straddle;
    no_retraction += local.no_retraction;
    aabb_cells += local.aabb_cells;
  });
  return {behind.load(), beyond.load(), straddle.load(), no_retraction.load(), aabb_cells.load()};
}

/// The triangles in order of nearest depth (ties: id) [Wang 2014 §4.2 takes a prefix sum of
/// cellsN in triangle order]: each cell's list is then sorted by depth, and a work item reads
/// only the prefix its deepest sample can be blocked by (the depth cut).
std::vector<uint32_t> depth_order(const std::vector<float>& zmins) {
  const size_t n = zmins.size();
  // Sorted as 64-bit keys (depth bits made to order like the values, id): a strict total order,
  // so the parallel sort's result is the serial one's, without a lookup per comparison.
  std::vector<uint64_t> keys(n);
  parallel_chunks(n, 16384, [&](size_t b, size_t e) {
    for (size_t t = b; t < e; ++t) {
      const uint32_t bits = std::bit_cast<uint32_t>(zmins[t] + 0.0f);  // −0 as +0
      const uint32_t ordered = bits & 0x80000000u ? ~bits : bits | 0x80000000u;
      keys[t] = uint64_t{ordered} << 32 | t;
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(keys[i]);
  return order;
}

/// Pass 2: the (triID, cellID) pairs, by cell [Wang 2014 §4.2 writes them, then sorts them on
/// cellID]. Written in cell order at once, by a counting sort fused with the write: the
/// depth-ordered triangles are cut into fixed chunks, each chunk counts its pairs per cell, the
/// offsets run over (cell, chunk), and each chunk writes at its own cursor per cell. The result
/// is the stable sort by cell of the depth-ordered pairs, without a sort's passes and buffer.
struct PairChunks {
  const Assignment& a;
  const std::vector<uint32_t>& order;
  size_t cell_count, chunks, per_chunk;
  std::vector<uint32_t> cursor;  // chunks × cells: each chunk's count, then its cursor, per cell

  // Fixed chunks (the result never depends on them nor on the threads); their cursors, chunks ×
  // cells words, stay below about half the pairs' own size.
  PairChunks(const Assignment& as, const std::vector<uint32_t>& o, uint64_t aabb_cells)
      : a(as),
        order(o),
        cell_count(static_cast<size_t>(as.cam.cell_count())),
        chunks(std::clamp<size_t>(aabb_cells / (2 * cell_count), 1, 16)),
        per_chunk((o.size() + chunks - 1) / chunks),
        cursor(chunks * cell_count, 0) {}

  /// Calls f(row, cell, triangle) for every pair, each chunk's in order with its own row of
  /// `cursor` (chunks in parallel).
  template <class F>
  void for_each_pair(F&& f) {
    const size_t n = order.size();
    parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
      for (size_t ch = c0; ch < c1; ++ch) {
        uint32_t* row = cursor.data() + ch * cell_count;
        for (size_t i = ch * per_chunk; i < std::min(n, (ch + 1) * per_chunk); ++i) {
          const uint32_t t = order[i];
          a.for_each_cell(t, [&](uint32_t c) { f(row, c, t); });
        }
      }
    });
  }

  /// The counts into each cell's [begin, end) and each chunk's cursors; returns the pair count.
  uint64_t offsets(CellTriangles& out) {
    out.begin.resize(cell_count);
    out.end.resize(cell_count);
    uint64_t running = 0;
    for (size_t c = 0; c < cell_count; ++c) {
      out.begin[c] = static_cast<uint32_t>(running);
      for (size_t ch = 0; ch < chunks; ++ch) {
        uint32_t& at = cursor[ch * cell_count + c];
        const uint32_t count = at;
        at = static_cast<uint32_t>(running);
        running += count;
      }
      out.end[c] = static_cast<uint32_t>(running);
    }
    return running;
  }
};

}  // namespace

PixelCells bucket_pixels(const GridCamera& camera, const std::vector<uint32_t>& pixels,
                         const std::vector<Vec3>& points) {
  PixelCells pc;
  const size_t n = pixels.size();
  pc.sorted.resize(n);
  parallel_chunks(n, 4096, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i)
      pc.sorted[i] = {static_cast<uint32_t>(camera.cell_of(points[i])), static_cast<uint32_t>(i)};
  });
  const uint32_t cells = static_cast<uint32_t>(camera.cell_count());
  radix_sort_by_cell(pc.sorted, cells);
  cell_ranges(pc.sorted, cells, pc.begin, pc.end);
  pc.max_z.assign(cells, -kInfinity);
  pc.sample_z.resize(n);
  pc.box_lo.assign(cells, Vec3(kInfinity));
  pc.box_hi.assign(cells, Vec3(-kInfinity));
  parallel_chunks(cells, 256, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c)
      for (uint32_t i = pc.begin[c]; i < pc.end[c]; ++i) {
        const Vec3& q = points[pc.sorted[i].item];
        pc.max_z[c] = std::max(pc.max_z[c], q.z);
        pc.box_lo[c] = glm::min(pc.box_lo[c], q);
        pc.box_hi[c] = glm::max(pc.box_hi[c], q);
      }
  });
  // Within a cell, nearest samples first: runs of consecutive samples then span few depths, so a
  // work item can drop the candidates that lie entirely deeper than its deepest sample.
  // Sorted as 64-bit keys (depth bits, index): depths are ≥ +0 here, whose IEEE bit patterns
  // order like the values; ties go to the lower index.
  parallel_chunks(cells, 64, [&](size_t b, size_t e) {
    std::vector<uint64_t> keys;
    for (size_t c = b; c < e; ++c) {
      keys.clear();
      for (uint32_t i = pc.begin[c]; i < pc.end[c]; ++i) {
        const uint32_t item = pc.sorted[i].item;
        keys.push_back(uint64_t{std::bit_cast<uint32_t>(points[item].z + 0.0f)} << 32 | item);
      }
      std::sort(keys.begin(), keys.end());
      for (uint32_t i = pc.begin[c]; i < pc.end[c]; ++i) {
        const uint32_t item = static_cast<uint32_t>(keys[i - pc.begin[c]]);
        pc.sorted[i].item = pixels[item];  // entries name the caller's pixel index from here on
        pc.sample_z[i] = points[item].z;
      }
    }
  });
  return pc;
}

CellTriangles assign_triangles(const GridCamera& cam, const TriangleSoup& soup, int side,
                               const PixelCells& cells, const AssignOptions& options,
                               AssignStats& stats) {
  Assignment a(cam, soup, side, cells, options);
  auto t0 = std::chrono::steady_clock::now();
  const PassCounts counts = count_pass(a);
  stats.count_ms += elapsed_ms(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<uint32_t> order = depth_order(a.zmins);
  stats.prefix_ms += elapsed_ms(t0);

  t0 = std::chrono::steady_clock::now();
  PairChunks chunks(a, order, counts.aabb_cells);
  chunks.for_each_pair([](uint32_t* count, uint32_t c, uint32_t) { ++count[c]; });
  CellTriangles out;
  const uint64_t pairs = chunks.offsets(out);
  if (pairs > UINT32_MAX)
    throw Error("gears: more than 2^32 (triangle, cell) pairs; use a coarser gears.grid");
  stats.sort_ms += elapsed_ms(t0);

  t0 = std::chrono::steady_clock::now();
  out.zmin = a.zmins;
  out.pairs.resize(pairs);
  chunks.for_each_pair([&](uint32_t* at, uint32_t c, uint32_t t) { out.pairs[at[c]++] = {c, t}; });
  stats.write_ms += elapsed_ms(t0);

  stats.pairs += out.pairs.size();
  stats.pairs_without_retraction += counts.no_retraction;
  stats.aabb_cells += counts.aabb_cells;
  stats.culled_behind_light += counts.behind;
  stats.culled_beyond_samples += counts.beyond;
  stats.straddling_light += counts.straddle;
  return out;
}

}  // namespace penumbra::gears
