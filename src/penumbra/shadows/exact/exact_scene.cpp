// ExactScene and ExactLight: the per-frame and per-light preparation of the exact reference,
// including the decomposition of alpha-textured triangles into their opaque pieces.
#include <tbb/parallel_invoke.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/scene/weld.hpp"
#include "penumbra/shadows/exact/edge_tree.hpp"
#include "penumbra/shadows/exact/exact.hpp"
#include "penumbra/shadows/exact/solid_interior.hpp"

namespace penumbra {

namespace {

/// Largest texel-cell count (rows × columns of its uv bounding box) one alpha-textured triangle may
/// span: beyond it the decomposition would take minutes, so the frame is refused with an Error.
constexpr double kMaxAlphaCells = double{1 << 26};

double cross2(const DVec2& a, const DVec2& b) {
  return a.x * b.y - a.y * b.x;
}

/// Sutherland–Hodgman of a convex uv polygon against sign · (q[axis] − bound) ≥ 0.
void clip_uv(std::vector<DVec2>& poly, std::vector<DVec2>& tmp, int axis, double bound,
             double sign) {
  tmp.clear();
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const DVec2& prev = poly[(i + n - 1) % n];
    const DVec2& cur = poly[i];
    const double fp = sign * (prev[axis] - bound), fc = sign * (cur[axis] - bound);
    if ((fc >= 0.0) != (fp >= 0.0)) {
      DVec2 x = prev + (fp / (fp - fc)) * (cur - prev);
      x[axis] = bound;
      tmp.push_back(x);
    }
    if (fc >= 0.0) tmp.push_back(cur);
  }
  poly.swap(tmp);
}

double polygon_area(const std::vector<DVec2>& poly) {
  double twice = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) twice += cross2(poly[i], poly[(i + 1) % poly.size()]);
  return 0.5 * twice;
}

struct AlphaPieces {
  bool whole = false;                      // the mask is opaque over the whole triangle
  std::vector<std::vector<DVec3>> pieces;  // otherwise: the opaque convex pieces (may be none)
};

/// The opaque part of a triangle under a nearest-texel alpha mask, exactly. Texel (tx, ty) covers
/// uv [tx/w, (tx+1)/w) × [ty/h, (ty+1)/h) repeated with period 1 (Texture::texel_index), so the
/// opaque set in uv is a union of axis-aligned texel rectangles; uv → world is affine on the
/// triangle, so each rectangle ∩ triangle maps to a convex world polygon.
///
/// Rows are scanned in absolute texel indices over the triangle's uv bounding box (any number of
/// texture periods, wrapping the lookup). In each row, runs of opaque texels form rectangles; a run
/// that reaches the triangle's extent in that row is extended to the bounding box's edge (the
/// triangle is not there, so it changes nothing), which lets identical runs of consecutive rows
/// merge into one taller rectangle: the fence mask's 64×64 texels become ~26 rectangles.
AlphaPieces decompose_alpha(const Texture& tex, const DVec2 uv[3], const DVec3 world[3]) {
  AlphaPieces out;
  const DVec2 e1 = uv[1] - uv[0], e2 = uv[2] - uv[0];
  const double det = cross2(e1, e2);
  DVec2 lo = glm::min(uv[0], glm::min(uv[1], uv[2])), hi = glm::max(uv[0], glm::max(uv[1], uv[2]));
  const DVec2 ext = hi - lo;
  const auto opaque_at = [&](int64_t column, int64_t row) {
    const int64_t w = tex.width, h = tex.height;
    const int tx = static_cast<int>(((column % w) + w) % w),
              ty = static_cast<int>(((row % h) + h) % h);
    return tex.channel(tx, ty, 0) >= kAlphaCutoff;
  };
  if (tex.width <= 0 || tex.height <= 0) {
    out.whole = true;  // no mask to read: validate_scene should have refused it; block everything
    return out;
  }
  if (!(std::abs(det) > 1e-14 * (ext.x * ext.x + ext.y * ext.y)) || !std::isfinite(det)) {
    // Degenerate uv mapping (e.g. a mesh without uvs: all zero): the whole triangle reads one
    // texel, the one at its uv centroid — the documented fallback.
    const Vec2 c((uv[0] + uv[1] + uv[2]) / 3.0);
    out.whole = tex.sample_scalar(c) >= kAlphaCutoff;
    return out;
  }

  const double w = tex.width, h = tex.height;
  const int64_t col_lo = static_cast<int64_t>(std::floor(lo.x * w)),
                col_hi = static_cast<int64_t>(std::floor(hi.x * w));
  const int64_t row_lo = static_cast<int64_t>(std::floor(lo.y * h)),
                row_hi = static_cast<int64_t>(std::floor(hi.y * h));
  const double cells =
      (static_cast<double>(col_hi - col_lo) + 1.0) * (static_cast<double>(row_hi - row_lo) + 1.0);
  if (!(cells <= kMaxAlphaCells)) {
    throw Error("exact: an alpha-textured triangle spans " +
                std::to_string(static_cast<long long>(cells)) + " texels of its mask (limit " +
                std::to_string(static_cast<long long>(kMaxAlphaCells)) + ")");
  }

  struct Rect {
    int64_t c0, c1, r0, r1;  // columns [c0, c1), rows [r0, r1)
  };
  struct Run {
    int64_t c0, c1, r0;
  };
  std::vector<Rect> rects;
  std::vector<Run> open, runs, still_open;
  std::vector<DVec2> poly, tmp;
  const DVec2 tri[3] = {uv[0], uv[1], uv[2]};

  for (int64_t row = row_lo; row <= row_hi + 1; ++row) {
    runs.clear();
    if (row <= row_hi) {
      poly.assign(tri, tri + 3);
      clip_uv(poly, tmp, 1, static_cast<double>(row) / h, 1.0);
      clip_uv(poly, tmp, 1, static_cast<double>(row + 1) / h, -1.0);
      if (poly.size() >= 3) {
        double umin = poly[0].x, umax = poly[0].x;
        for (const DVec2& q : poly) {
          umin = std::min(umin, q.x);
          umax = std::max(umax, q.x);
        }
        const int64_t first =
            std::clamp(static_cast<int64_t>(std::floor(umin * w)), col_lo, col_hi);
        const int64_t last = std::clamp(static_cast<int64_t>(std::floor(umax * w)), col_lo, col_hi);
        for (int64_t c = first; c <= last;) {
          if (!opaque_at(c, row)) {
            ++c;
            continue;
          }
          int64_t end = c;
          while (end <= last && opaque_at(end, row)) ++end;
          runs.push_back({c == first ? col_lo : c, end == last + 1 ? col_hi + 1 : end, row});
          c = end;
        }
      }
    }
    // Runs identical to an open one extend it; open runs not continued are closed.
    still_open.clear();
    for (const Run& o : open) {
      const auto it = std::find_if(runs.begin(), runs.end(),
                                   [&](const Run& r) { return r.c0 == o.c0 && r.c1 == o.c1; });
      if (it != runs.end()) {
        still_open.push_back(o);
        runs.erase(it);
      } else {
        rects.push_back({o.c0, o.c1, o.r0, row});
      }
    }
    for (const Run& r : runs) still_open.push_back(r);
    open.swap(still_open);
  }

  if (rects.size() == 1 && rects[0].c0 == col_lo && rects[0].c1 == col_hi + 1 &&
      rects[0].r0 == row_lo && rects[0].r1 == row_hi + 1) {
    out.whole = true;
    return out;
  }
  const double min_area = 1e-14 * std::abs(det);
  for (const Rect& r : rects) {
    poly.assign(tri, tri + 3);
    clip_uv(poly, tmp, 0, static_cast<double>(r.c0) / w, 1.0);
    clip_uv(poly, tmp, 0, static_cast<double>(r.c1) / w, -1.0);
    clip_uv(poly, tmp, 1, static_cast<double>(r.r0) / h, 1.0);
    clip_uv(poly, tmp, 1, static_cast<double>(r.r1) / h, -1.0);
    if (poly.size() < 3 || std::abs(polygon_area(poly)) <= min_area) continue;
    std::vector<DVec3> piece;
    piece.reserve(poly.size());
    for (const DVec2& q : poly) {
      // Barycentrics of q in the uv triangle, applied to the world triangle (affine map).
      const DVec2 d = q - uv[0];
      const double b1 = cross2(d, e2) / det, b2 = cross2(e1, d) / det;
      piece.push_back(world[0] + b1 * (world[1] - world[0]) + b2 * (world[2] - world[0]));
    }
    if (piece.size() <= static_cast<size_t>(kMaxPolygon)) {
      out.pieces.push_back(std::move(piece));
    } else {
      // Triangle ∩ rectangle has at most 7 vertices; should rounding ever add more, split the
      // convex piece into a fan so project_polygon never refuses it.
      for (size_t j = 1; j + 1 < piece.size(); ++j)
        out.pieces.push_back({piece[0], piece[j], piece[j + 1]});
    }
  }
  return out;
}

/// The caps that close `mesh` into a 2-cycle (ExactSolid). `weld`: weld_positions of its vertices
/// (scene/weld.hpp); every directed edge a→b counts +1 on the undirected edge and
/// b→a −1, and an edge left with net n ≠ 0 is |n| boundary edges in the direction of its sign. At
/// every vertex as many boundary edges leave as arrive (each triangle is a cycle), so they split
/// into closed walks; the reversed fan over each walk has minus that walk as its boundary, so
/// mesh + fans has none. False when more than kMaxCapTriangles would be needed.
bool make_caps(const Mesh& mesh, const std::vector<uint32_t>& weld, ExactSolid& solid) {
  // Net multiplicity of each undirected welded edge (+1 per use lo → hi): sorted keys instead of
  // a hash map, which took ~5 % of `exact` at 256² on the large models.
  std::vector<uint64_t> uses;  // (lo << 32 | hi) << 1 | (1 when used hi → lo)
  uses.reserve(3 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = weld[t.v[e]], b = weld[t.v[(e + 1) % 3]];
      if (a == b) continue;
      uses.push_back((uint64_t{std::min(a, b)} << 32 | std::max(a, b)) << 1 | (a < b ? 0 : 1));
    }
  std::sort(uses.begin(), uses.end());
  std::unordered_map<uint32_t, std::vector<uint32_t>> out;  // boundary edges leaving a vertex
  size_t boundary = 0;
  for (size_t i = 0; i < uses.size();) {
    const uint64_t edge = uses[i] >> 1;
    int n = 0;
    for (; i < uses.size() && uses[i] >> 1 == edge; ++i) n += (uses[i] & 1) != 0 ? -1 : 1;
    const uint32_t lo = static_cast<uint32_t>(edge >> 32), hi = static_cast<uint32_t>(edge);
    if (boundary + static_cast<size_t>(std::abs(n)) > kMaxCapTriangles) return false;
    for (int k = 0; k < std::abs(n); ++k) {
      if (n > 0)
        out[lo].push_back(hi);
      else
        out[hi].push_back(lo);
      ++boundary;
    }
  }
  if (boundary > kMaxCapTriangles) return false;
  // Walks in a deterministic order (by start vertex).
  std::vector<uint32_t> starts;
  for (const auto& [v, list] : out) starts.push_back(v);
  std::sort(starts.begin(), starts.end());
  for (auto& [v, list] : out) std::sort(list.begin(), list.end());
  for (const uint32_t start : starts) {
    while (!out[start].empty()) {
      std::vector<uint32_t> walk{start};
      uint32_t at = out[start].back();
      out[start].pop_back();
      while (at != start) {
        walk.push_back(at);
        std::vector<uint32_t>& next = out[at];
        if (next.empty()) return false;  // cannot happen for a sum of cycles
        const uint32_t to = next.back();
        next.pop_back();
        at = to;
      }
      Bounds3 box;
      for (const uint32_t v : walk) box.extend(mesh.positions[v]);
      for (size_t i = 1; i + 1 < walk.size(); ++i)
        solid.caps.push_back({DVec3(mesh.positions[walk[0]]), DVec3(mesh.positions[walk[i + 1]]),
                              DVec3(mesh.positions[walk[i]])});
      if (walk.size() >= 3) solid.cap_boxes.push_back(box);
    }
  }
  return solid.caps.size() <= kMaxCapTriangles;
}

/// Fills ExactOccluder::neighbour for the opaque uncut triangles: corners welded by position within
/// a mesh (`welds`: weld_positions per mesh, scene/weld.hpp), an edge paired only when exactly two
/// triangles use it, in opposite directions. Occluder t is triangle tri_of[t] of mesh mesh_of[t].
/// The edges are sorted, not hashed: deterministic.
void link_neighbours(std::vector<ExactOccluder>& occluders, const Scene& scene,
                     const std::vector<std::vector<uint32_t>>& welds,
                     const std::vector<uint32_t>& mesh_of, const std::vector<uint32_t>& tri_of) {
  std::vector<uint32_t> vertex_base(scene.meshes.size() + 1, 0);  // welded ids, offset per mesh
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    vertex_base[m + 1] = vertex_base[m] + static_cast<uint32_t>(welds[m].size());
  std::vector<uint32_t> vertex_of(3 * occluders.size(), 0xFFFFFFFFu);
  for (size_t t = 0; t < occluders.size(); ++t) {
    const ExactOccluder& o = occluders[t];
    if (o.cut || o.transmittance > 0.0) continue;
    const uint32_t m = mesh_of[t];
    const Triangle& tri = scene.meshes[m].triangles[tri_of[t]];
    for (int c = 0; c < 3; ++c) vertex_of[3 * t + c] = vertex_base[m] + welds[m][tri.v[c]];
  }
  struct Edge {
    uint32_t lo, hi, slot;  // slot: occluder · 3 + edge; lo→hi is the forward direction
    bool forward;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * occluders.size());
  for (size_t t = 0; t < occluders.size(); ++t) {
    const uint32_t a0 = vertex_of[3 * t];
    if (a0 == 0xFFFFFFFFu) continue;
    for (uint32_t e = 0; e < 3; ++e) {
      const uint32_t a = vertex_of[3 * t + e], b = vertex_of[3 * t + (e + 1) % 3];
      if (a == b) continue;
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<uint32_t>(3 * t + e), a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.lo, x.hi, x.slot) < std::tie(y.lo, y.hi, y.slot);
  });
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    if (j - i == 2 && edges[i].forward != edges[i + 1].forward) {
      const Edge &x = edges[i], &y = edges[i + 1];
      occluders[x.slot / 3].neighbour[x.slot % 3] = y.slot / 3;
      occluders[y.slot / 3].neighbour[y.slot % 3] = x.slot / 3;
    }
    i = j;
  }
}

/// Fills cones[index] for the subtree at `index` (occluders already in leaf order, so a subtree
/// owns a contiguous range) and returns that range.
std::pair<uint32_t, uint32_t> make_node_cones(const ExactBvh& bvh,
                                              const std::vector<ExactOccluder>& occluders,
                                              const std::vector<DVec3>& unit_normals,
                                              uint32_t index, std::vector<ExactNodeCone>& cones) {
  const ExactBvh::Node& node = bvh.nodes()[index];
  std::pair<uint32_t, uint32_t> range{node.first, node.first + node.count};
  if (node.count == 0) {
    const auto left = make_node_cones(bvh, occluders, unit_normals, index + 1, cones);
    const auto right = make_node_cones(bvh, occluders, unit_normals, node.first, cones);
    range = {std::min(left.first, right.first), std::max(left.second, right.second)};
  }
  ExactNodeCone& cone = cones[index];
  cone.triangles = range.second - range.first;
  const uint32_t solid = occluders[range.first].solid;
  for (uint32_t t = range.first; t < range.second; ++t)
    if (occluders[t].solid != solid || occluders[t].cut) return range;
  if (solid == ExactOccluder::kNotSolid) return range;
  const std::span<const DVec3> normals(unit_normals.data() + range.first,
                                       range.second - range.first);
  if (!fit_normal_cone(normals, node, cone)) return range;
  cone.solid = solid;
  return range;
}

}  // namespace

ExactScene::ExactScene(const Scene& scene, int leaf_size, bool cull_back_faces, bool edge_trees)
    : scene_(&scene) {
  // The set-up is a frame's serial start (≈ 45 ms on 20 k triangles): its independent parts run
  // side by side — the caps beside the occluders, the adjacency beside the BVH.
  // Opaque uncut meshes: candidates for back-face culling, closed by caps where they are open.
  std::vector<uint32_t> solid_of_mesh(scene.meshes.size(), ExactOccluder::kNotSolid);
  // Welded vertices of the meshes that can hold opaque uncut triangles (the caps' and the
  // neighbour links' input); empty for the others.
  std::vector<std::vector<uint32_t>> welds(scene.meshes.size());
  tbb::task_group caps_task;
  caps_task.run([&] {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      const Mesh& mesh = scene.meshes[m];
      if (mesh.casts_shadows && scene.material_of(mesh).transmittance <= 0.0f)
        welds[m] = weld_positions(mesh.positions);
    }
    if (!cull_back_faces) return;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      const Mesh& mesh = scene.meshes[m];
      const Material& mat = scene.material_of(mesh);
      if (!mesh.casts_shadows || mat.transmittance > 0.0f || mat.alpha_texture >= 0) continue;
      ExactSolid solid;
      if (!make_caps(mesh, welds[m], solid)) continue;
      solid.mesh = static_cast<uint32_t>(m);
      for (const Vec3& v : mesh.positions) solid.box.extend(v);
      for (const auto& cap : solid.caps) {
        Bounds3& box = solid.cap_triangle_boxes.emplace_back();
        for (const DVec3& v : cap) box.extend(Vec3(v));
      }
      solid_of_mesh[m] = static_cast<uint32_t>(solids_.size());
      solids_.push_back(solid);
    }
  });

  struct Item {
    uint32_t mesh, tri;
  };
  std::vector<Item> items;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.casts_shadows) continue;
    const Material& mat = scene.material_of(mesh);
    if (mat.transmittance >= 1.0f) continue;  // lets all light through: blocks nothing
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const DVec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
      const double area2 = glm::length(glm::cross(b - a, c - a));
      // A zero-area (or non-finite) triangle blocks a set of measure zero.
      if (!(area2 > 0.0) || !std::isfinite(area2)) continue;
      items.push_back({static_cast<uint32_t>(m), static_cast<uint32_t>(t)});
    }
  }

  // Alpha pieces: independent per triangle, so in parallel; flattened in item order afterwards
  // (deterministic layout).
  std::vector<AlphaPieces> alpha(items.size());
  parallel_chunks(items.size(), 256, [&](size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      const Mesh& mesh = scene.meshes[items[k].mesh];
      const Material& mat = scene.material_of(mesh);
      if (mat.alpha_texture < 0) continue;
      const size_t t = items[k].tri;
      DVec2 uv[3];
      DVec3 world[3];
      for (int i = 0; i < 3; ++i) {
        uv[i] = mesh.uvs.empty() ? DVec2(0.0) : DVec2(mesh.uvs[mesh.triangles[t].v[i]]);
        world[i] = DVec3(mesh.vertex(t, i));
      }
      alpha[k] = decompose_alpha(scene.textures[mat.alpha_texture], uv, world);
    }
  });

  std::vector<Bounds3> boxes;
  std::vector<uint32_t> occluder_mesh, occluder_tri;
  occluders_.reserve(items.size());
  boxes.reserve(items.size());
  for (size_t k = 0; k < items.size(); ++k) {
    const Mesh& mesh = scene.meshes[items[k].mesh];
    const Material& mat = scene.material_of(mesh);
    ExactOccluder o;
    Bounds3 box;
    for (int i = 0; i < 3; ++i) {
      o.v[i] = DVec3(mesh.vertex(items[k].tri, i));
      box.extend(mesh.vertex(items[k].tri, i));
    }
    o.transmittance = std::max(0.0, static_cast<double>(mat.transmittance));
    if (mat.alpha_texture >= 0 && !alpha[k].whole) {
      if (alpha[k].pieces.empty()) continue;  // all holes
      o.cut = true;
      o.piece_first = static_cast<uint32_t>(pieces_.size());
      o.piece_count = static_cast<uint32_t>(alpha[k].pieces.size());
      for (const std::vector<DVec3>& piece : alpha[k].pieces) {
        pieces_.push_back(
            {static_cast<uint32_t>(piece_vertices_.size()), static_cast<uint32_t>(piece.size())});
        piece_vertices_.insert(piece_vertices_.end(), piece.begin(), piece.end());
      }
    }
    o.normal = glm::cross(o.v[1] - o.v[0], o.v[2] - o.v[0]);
    semi_opaque_ = semi_opaque_ || o.transmittance > 0.0;
    occluders_.push_back(o);
    occluder_mesh.push_back(items[k].mesh);
    occluder_tri.push_back(items[k].tri);
    boxes.push_back(box);
  }
  caps_task.wait();
  for (size_t k = 0; k < occluders_.size(); ++k)
    occluders_[k].solid = solid_of_mesh[occluder_mesh[k]];
  tbb::parallel_invoke(
      [&] { link_neighbours(occluders_, scene, welds, occluder_mesh, occluder_tri); },
      [&] { bvh_.build(boxes, leaf_size); });
  // Occluders in leaf order: a pixel's candidates are then read from a few runs of memory.
  const std::vector<uint32_t>& order = bvh_.primitives();
  std::vector<uint32_t> new_index(order.size());
  for (size_t k = 0; k < order.size(); ++k) new_index[order[k]] = static_cast<uint32_t>(k);
  std::vector<ExactOccluder> sorted(occluders_.size());
  for (size_t k = 0; k < order.size(); ++k) {
    sorted[k] = occluders_[order[k]];
    for (uint32_t& nb : sorted[k].neighbour)
      if (nb != ExactOccluder::kNoNeighbour) nb = new_index[nb];
  }
  occluders_.swap(sorted);
  neighbours_.resize(occluders_.size());
  for (size_t k = 0; k < occluders_.size(); ++k)
    std::copy(std::begin(occluders_[k].neighbour), std::end(occluders_[k].neighbour),
              neighbours_[k].begin());
  bvh_.renumber_in_leaf_order();
  std::vector<std::vector<uint32_t>> triangles(solids_.size());
  for (uint32_t t = 0; t < occluders_.size(); ++t)
    if (occluders_[t].solid != ExactOccluder::kNotSolid)
      triangles[occluders_[t].solid].push_back(t);
  for (uint32_t s = 0; s < solids_.size(); ++s) {
    if (!edge_trees || triangles[s].size() < kEdgeTreeMinTriangles) continue;
    solids_[s].edge_tree = static_cast<int32_t>(edge_tree_solids_.size());
    edge_tree_solids_.push_back(s);
  }
  edge_trees_.resize(edge_tree_solids_.size());
  // The node cones, the solids' inner balls and the edge trees (all read the ordered occluders).
  tbb::parallel_invoke(
      [&] {
        if (solids_.empty() || bvh_.empty()) return;
        node_cones_.resize(bvh_.nodes().size());
        std::vector<DVec3> unit_normals(occluders_.size());
        for (size_t t = 0; t < occluders_.size(); ++t)
          unit_normals[t] = glm::normalize(occluders_[t].normal);
        make_node_cones(bvh_, occluders_, unit_normals, 0, node_cones_);
      },
      [&] {
        // Largest first (ties by index): many small solids cannot spend a large one's budget.
        std::vector<uint32_t> by_size(solids_.size());
        for (uint32_t s = 0; s < by_size.size(); ++s) by_size[s] = s;
        std::stable_sort(by_size.begin(), by_size.end(), [&](uint32_t a, uint32_t b) {
          return triangles[a].size() > triangles[b].size();
        });
        size_t budget = kInnerBallBudget;
        for (const uint32_t s : by_size) {
          solids_[s].balls = find_inner_balls(*this, s, triangles[s], budget);
          solids_[s].ball_groups = group_inner_balls(solids_[s].balls, solids_[s].box);
        }
      },
      [&] {
        parallel_chunks(edge_tree_solids_.size(), 1, [&](size_t k0, size_t k1) {
          for (size_t k = k0; k < k1; ++k) {
            const uint32_t s = edge_tree_solids_[k];
            edge_trees_[k] = build_edge_tree(occluders_, triangles[s], s, leaf_size);
          }
        });
      });
}

ExactLight::ExactLight(const Scene& scene, const Light& light, int disk_segments)
    : light_(&light),
      outline_(make_light_outline(
          light.shape == LightShape::disk || light.shape == LightShape::sphere, disk_segments)) {
  if (!light.is_textured()) return;
  if (light.emission_texture >= static_cast<int>(scene.textures.size())) {
    throw Error("exact: light '" + light.name + "' names emission texture " +
                std::to_string(light.emission_texture) + " of " +
                std::to_string(scene.textures.size()));
  }
  const Texture& tex = scene.textures[light.emission_texture];
  if (tex.width <= 0 || tex.height <= 0)
    throw Error("exact: empty emission texture '" + tex.name + "'");
  texture_width_ = tex.width;
  texture_height_ = tex.height;
  texel_weight_.resize(static_cast<size_t>(tex.width) * tex.height);
  // The same weight as the sampling methods give a sample in this texel (light_weights.hpp):
  // the texture's RGB (grey for one channel) times the light's radiance.
  for (int ty = 0; ty < tex.height; ++ty) {
    for (int tx = 0; tx < tex.width; ++tx) {
      const DVec3 rgb = tex.channels < 3 ? DVec3(tex.channel(tx, ty, 0))
                                         : DVec3(tex.channel(tx, ty, 0), tex.channel(tx, ty, 1),
                                                 tex.channel(tx, ty, 2));
      texel_weight_[static_cast<size_t>(ty) * tex.width + tx] = rgb * DVec3(light.radiance);
    }
  }
  total_weight_ =
      texel_weighted_area({outline_.path}, texture_width_, texture_height_, texel_weight_);
}

}  // namespace penumbra
