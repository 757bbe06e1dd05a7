// `gears`: exact soft shadows from per-pixel sets of potentially blocking triangles [Wang 2014 §3,
// §4.2] on the CPU. Steps: (3.1) grid camera C over the pixel samples; (3.2) samples → cells;
// (3.3) triangles → cells through their projected shadow volumes, with the retraction; (4) per
// pixel, the candidate triangles of its cell rasterized onto the k×k light-sample bitmask by edge
// planes (batched SIMD setup, row spans) or by the LUT [§4.3]; (5) V from the bits, weighted by
// light_weights.hpp exactly as `raytrace` weights its rays.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <memory>
#include <optional>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/lut.hpp"
#include "penumbra/shadows/gears/raster.hpp"
#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

using namespace gears;

struct Options {
  int grid = 0;  // 0: grid_resolution's choice for the image
  bool lut = false;
  int lut_resolution = 256;
  AssignOptions assign;
  float eye_distance = 1.0f;
  int chunk = 32;
  bool pixel_cull = true;
  int group = 8;
  int long_chunk = 4;
  bool hidden_cull = true;
  bool deepest_first = true;
  bool box_cull = true;
  bool solid_cull = true;
};

/// Cell lists longer than this get work items of `long_chunk` × `chunk` samples (items loop).
constexpr uint64_t kLongCellList = 2048;

/// Per-thread buffers of the rasterization pass.
struct Scratch {
  CandidateBatch batch, group_batch, pixel_batch;  // a work item's candidates, a group's, a pixel's
  std::vector<int> group_order, group_ends;        // the item's samples in groups (group_samples)
  LineBatch lines;
  std::vector<Vec2> light_uv;
  std::vector<float> su, sv, vis, trans;  // trans: the pixel's per-sample transmittance
  std::vector<Vec2> shade_uv;
  std::vector<float> ix, iy, iz;  // the work item's samples, for its cull bounds
  std::vector<float> gx, gy, gz;  // one group's
  std::vector<Vec3> gp;           // one group's samples (unmirrored light space)
  std::vector<uint64_t> outside;  // the item's samples: Solids::outside
  std::vector<uint64_t> cover, blocked;
  std::vector<uint64_t> own;        // a pixel's mask words, where the frame holds none
  uint32_t rows[32], tri_rows[32];  // k ≤ 32 rows (row spans write whole 16-row registers)
};

class Gears final : public ShadowMethod {
 public:
  explicit Gears(const Options& o) : opt_(o) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    const Light& light = ctx.light;
    const int n = ctx.samples.count();
    const int k = ctx.samples.k();
    const bool point = light.shape == LightShape::point;
    const bool sphere = light.shape == LightShape::sphere;
    const bool per_pixel_samples = ctx.samples.per_pixel();
    const Texture* emission =
        light.is_textured() ? &ctx.scene.textures[light.emission_texture] : nullptr;
    const int words = (n + 63) / 64;

    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    if (emission) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));

    // Which rasterizer: row spans need the regular grid (sample i in cell (i % k, i / k) at its
    // centre); the LUT needs shared positions; everything else tests sample by sample.
    const bool grid_pattern =
        ctx.samples.spec().pattern == SamplePattern::grid && !per_pixel_samples;
    const bool use_lut = opt_.lut && !per_pixel_samples && !point;
    const bool use_rows = !use_lut && grid_pattern && k <= 32 && !point;

    // ---- Step 2/3.2 prologue: active pixel samples in light space.
    auto t0 = std::chrono::steady_clock::now();
    const std::vector<uint32_t> active =
        parallel_indices(g.pixel_count(), [&](size_t i) { return ctx.receivers[i] == kActive; });
    const uint64_t back_facing = static_cast<uint64_t>(
        std::count(ctx.receivers.pixels().begin(), ctx.receivers.pixels().end(), kBackFacing));
    const LightFrame frame0 = light_frame(light, light.center + Vec3(0.0f, -1.0f, 0.0f));
    Vec3 toward = frame0.emit_normal;
    if (point || sphere) {
      Bounds3 b;
      for (uint32_t i : active) b.extend(g.shadow_origin(i));
      toward = b.empty() ? Vec3(0.0f, -1.0f, 0.0f) : b.center() - light.center;
    }
    const LightSpace space = make_light_space(light, frame0, toward, +1);
    std::vector<Vec3> p_light(active.size());
    parallel_chunks(active.size(), 4096, [&](size_t b, size_t e) {
      for (size_t a = b; a < e; ++a) p_light[a] = space.to_light(g.shadow_origin(active[a]));
    });

    // Occluders in light space.
    TriangleSoup soup;
    bool any_translucent = false;  // alpha-textured or semi-opaque
    bool any_semi_opaque = false;
    // Each shadow-casting mesh's triangles from its offset on, filled in parallel.
    std::vector<size_t> first_of(ctx.scene.meshes.size() + 1, 0);
    std::vector<uint8_t> mesh_opaque(ctx.scene.meshes.size(), 0);
    for (size_t m = 0; m < ctx.scene.meshes.size(); ++m) {
      const Mesh& mesh = ctx.scene.meshes[m];
      first_of[m + 1] = first_of[m] + (mesh.casts_shadows ? mesh.triangle_count() : 0);
      if (!mesh.casts_shadows) continue;
      mesh_opaque[m] = ctx.scene.material_of(mesh).is_opaque() ? 1 : 0;
      any_translucent |= !mesh_opaque[m];
      any_semi_opaque |= ctx.scene.material_of(mesh).transmittance > 0.0f;
    }
    const size_t tri_count = first_of.back();
    soup.resize(tri_count);
    parallel_chunks(tri_count, 4096, [&](size_t b, size_t e) {
      size_t m = std::upper_bound(first_of.begin(), first_of.end(), b) - first_of.begin() - 1;
      for (size_t t = b; t < e; ++t) {
        while (t >= first_of[m + 1]) ++m;  // skips the meshes that cast no shadow
        const Mesh& mesh = ctx.scene.meshes[m];
        const size_t prim = t - first_of[m];
        soup.mesh[t] = static_cast<uint32_t>(m);
        soup.prim[t] = static_cast<uint32_t>(prim);
        soup.opaque[t] = mesh_opaque[m];
        for (int c = 0; c < 3; ++c) {
          const Vec3 q = space.to_light(mesh.vertex(prim, c));
          soup.x[c][t] = q.x, soup.y[c][t] = q.y, soup.z[c][t] = q.z;
        }
      }
    });
    vis.times.add("light_space_setup", elapsed_ms(t0));
    // The solids are first needed to pack the triangles: found meanwhile, as one task (the
    // pixel and grid set-up below leave cores idle part of the time).
    Solids solids;
    double solids_ms = 0.0;
    tbb::task_group solids_task;
    if (opt_.solid_cull)
      solids_task.run([&] {
        const auto start = std::chrono::steady_clock::now();
        solids = find_solids(ctx.scene, soup);
        solids_ms = elapsed_ms(start);
      });
    bool solids_ready = !opt_.solid_cull;
    auto wait_for_solids = [&] {
      if (solids_ready) return;
      const auto start = std::chrono::steady_clock::now();
      solids_task.wait();
      solids_ready = true;
      vis.times.add("find_solids_wait", elapsed_ms(start));
    };

    // Light corners in light space, for the extrusion.
    std::vector<Vec3> corners;
    float light_max_z = 0.0f;
    if (point) {
      corners = {Vec3(0.0f)};
    } else {
      const float r = sphere ? light.radius / glm::length(space.axis_n) : 0.0f;  // in z units
      light_max_z = r;
      for (float z : sphere ? std::vector<float>{-r, r} : std::vector<float>{0.0f})
        for (int c = 0; c < 4; ++c)
          corners.emplace_back(static_cast<float>(c & 1), static_cast<float>(c >> 1), z);
    }

    // Shared sample positions (light uv) and, for round lights, which emit.
    std::vector<Vec2> shared(n);
    if (!per_pixel_samples) ctx.samples.pixel_samples(0, 0, shared);
    Vec2 uv_lo(0.0f), uv_hi(1.0f);
    if (!per_pixel_samples) {
      uv_lo = Vec2(kInfinity), uv_hi = Vec2(-kInfinity);
      for (const Vec2& s : shared) uv_lo = glm::min(uv_lo, s), uv_hi = glm::max(uv_hi, s);
    }
    // Pixels no occluder's box can shadow (most of a frame, for a rectangle or disk light with
    // shared samples): left out of the grid passes, their masks stay zero. The boxes are in light
    // space, per shadow-casting mesh (up to kMaxCullBoxes of them).
    t0 = std::chrono::steady_clock::now();
    std::vector<uint8_t> may_be_shadowed(active.size(), 1);
    uint64_t box_culled = 0;
    constexpr size_t kMaxCullBoxes = 256;
    if (opt_.box_cull && !per_pixel_samples && !point && !sphere) {
      FlatLight light_box;
      light_box.flat = true;
      light_box.lx0 = uv_lo.x, light_box.lx1 = uv_hi.x, light_box.ly0 = uv_lo.y,
      light_box.ly1 = uv_hi.y;
      std::vector<PackedTriangle> boxes;
      for (const Mesh& mesh : ctx.scene.meshes) {
        if (!mesh.casts_shadows || mesh.triangle_count() == 0) continue;
        const Bounds3 world = mesh.bounds();
        Vec3 lo(kInfinity), hi(-kInfinity);
        for (int c = 0; c < 8; ++c) {
          const Vec3 q =
              space.to_light(Vec3(c & 1 ? world.hi.x : world.lo.x, c & 2 ? world.hi.y : world.lo.y,
                                  c & 4 ? world.hi.z : world.lo.z));
          lo = glm::min(lo, q), hi = glm::max(hi, q);
        }
        boxes.push_back(box_cull_bounds(light_box, lo, hi));
      }
      if (boxes.size() <= kMaxCullBoxes) {
        std::atomic<uint64_t> culled{0};
        parallel_chunks(active.size(), 4096, [&](size_t b, size_t e) {
          uint64_t local = 0;
          for (size_t a = b; a < e; ++a) {
            const Vec3& q = p_light[a];
            const ItemBounds own = item_bounds(light_box, &q.x, &q.y, &q.z, 1);
            bool any = !(q.z > 0.0f);
            for (size_t i = 0; i < boxes.size() && !any; ++i) any = may_block(boxes[i], own);
            may_be_shadowed[a] = any;
            local += !any;
          }
          culled += local;
        });
        box_culled = culled.load();
      }
    }
    vis.times.add("pixel_box_cull", elapsed_ms(t0));
    std::unique_ptr<EdgeLut> lut;
    if (use_lut) lut = std::make_unique<EdgeLut>(shared, opt_.lut_resolution, opt_.lut_resolution);
    std::vector<float> shared_u(n), shared_v(n);
    for (int s = 0; s < n; ++s) shared_u[s] = shared[s].x, shared_v[s] = shared[s].y;
    std::vector<uint64_t> emit_words(words, 0);
    int emit_count = 0;
    for (int s = 0; s < n; ++s)
      if (!per_pixel_samples && frame0.emits(shared[s]))
        emit_words[s >> 6] |= uint64_t{1} << (s & 63), ++emit_count;
    const bool simple_weights = !emission && !per_pixel_samples && !point;
    // Each pixel's bits are produced in its work item. The frame's array holds them when they are
    // asked for or when step 5 shades from them (weighted lights, semi-opaque occluders);
    // otherwise each pixel is shaded from its own bits at once, and the pixels no pass reaches
    // keep V = 1 (no bit set): no frame-size array to clear (32 MB at 1024², k 16) nor to read.
    const bool shade_in_place =
        !ctx.want_masks && simple_weights && !any_translucent && emit_count > 0;
    // A pixel takes its candidates' chunks deepest first, nearest to itself: an umbra's front
    // layer then fills its mask early, and what lies behind that layer is hidden (same bits: the
    // mask is the union of the covered samples, alpha-tested ones included). Semi-opaque occluders
    // keep the list's order, so that their transmittance products are formed in one order
    // whatever the options.
    const bool deepest_first = opt_.deepest_first && !any_semi_opaque;
    SampleMasks masks;
    if (!shade_in_place) masks = SampleMasks(g.width, g.height, n);

    AssignStats astats;
    std::atomic<uint64_t> from_grid{0}, gathered{0}, item_kept{0}, group_kept{0}, pixel_scanned{0},
        tested{0}, hidden{0}, in_volume{0}, necessary{0}, early_full{0};
    uint64_t tris_max = 0, samples_max = 0, nonempty_cells = 0, sum_tris = 0, sum_samples = 0;
    double raster_ms = 0.0, project_ms = 0.0;
    size_t peak_bytes = 0;

    tbb::enumerable_thread_specific<Scratch> scratch;

    // Step 5 for one pixel: V from its mask words `m` (and transmittances `tr`, semi-opaque
    // occluders only).
    auto shade = [&](uint32_t pix, const uint64_t* m, const float* tr, Scratch& sc) {
      if (simple_weights && !tr) {
        int blocked = 0;
        for (int i = 0; i < words; ++i) blocked += std::popcount(m[i] & emit_words[i]);
        SampleWeights w;
        w.visible = Vec3(static_cast<float>(emit_count - blocked));
        w.total = Vec3(static_cast<float>(emit_count));
        vis.lit[pix] = w.visible_fraction();
        return;
      }
      const LightFrame frame = light_frame(light, g.shadow_origin(pix));
      sc.shade_uv.resize(n);
      sc.vis.resize(n);
      ctx.samples.pixel_samples(static_cast<int>(pix % g.width), static_cast<int>(pix / g.width),
                                sc.shade_uv);
      for (int s = 0; s < n; ++s) {
        const bool blk = (m[s >> 6] >> (s & 63)) & 1u;
        sc.vis[s] = blk ? 0.0f : (tr ? tr[s] : 1.0f);
      }
      const SampleWeights w =
          accumulate_sample_weights(frame, emission, light.radiance, sc.shade_uv, sc.vis);
      vis.lit[pix] = w.visible_fraction();
      if (emission) vis.lit_rgb->operator[](pix) = w.visible_fraction_rgb();
    };

    // One grid pass per side of the light plane that has samples.
    for (int side : {+1, -1}) {
      t0 = std::chrono::steady_clock::now();
      // The grid spans every sample of the side (its cells then do not depend on the box cull),
      // only the samples that may be shadowed are bucketed.
      auto on_side = [&](size_t a) { return (side > 0) == (p_light[a].z >= 0.0f); };
      const std::vector<uint32_t> ids = parallel_indices(
          active.size(), [&](size_t a) { return may_be_shadowed[a] && on_side(a); });
      if (ids.empty()) continue;
      auto mirrored = [&](const std::vector<uint32_t>& from) {
        std::vector<Vec3> to(from.size());
        parallel_chunks(from.size(), 4096, [&](size_t b, size_t e) {
          for (size_t i = b; i < e; ++i) {
            const Vec3& q = p_light[from[i]];
            to[i] = Vec3(q.x, q.y, side * q.z);
          }
        });
        return to;
      };
      const std::vector<Vec3> pts = mirrored(ids);
      // Every sample on the light's front (the usual case): the side's points are p_light itself.
      std::vector<Vec3> side_copy;
      const bool all_front = side > 0 && std::all_of(p_light.begin(), p_light.end(),
                                                     [](const Vec3& q) { return q.z >= 0.0f; });
      if (!all_front) side_copy = mirrored(parallel_indices(active.size(), on_side));
      const std::vector<Vec3>& side_pts = all_front ? p_light : side_copy;
      const LightSpace side_space = make_light_space(light, frame0, toward, side);
      const GridCamera cam =
          make_grid_camera(side_space, corners, light_max_z, side_pts, opt_.eye_distance,
                           grid_resolution(opt_.grid, g.width, g.height));
      side_copy = {};
      const PixelCells cells = bucket_pixels(cam, ids, pts);
      project_ms += elapsed_ms(t0);

      const CellTriangles table = assign_triangles(cam, soup, side, cells, opt_.assign, astats);
      FlatLight flat = flat_light(cam);
      if (!per_pixel_samples && !point && !sphere) flat = shrink_to_samples(flat, uv_lo, uv_hi);
      wait_for_solids();
      UninitVector<PackedTriangle> packed = pack_triangles(soup, side, table.zmin, flat);
      if (solids.count() > 0)
        for (size_t t = 0; t < tri_count; ++t) packed[t].solid = solids.of_triangle[t];
      const UninitVector<TrianglePlane> planes =
          triangle_planes(soup, plane_test_corners(flat, cam));
      peak_bytes = std::max(peak_bytes, table.bytes() + packed.size() * sizeof(PackedTriangle) +
                                            planes.size() * sizeof(TrianglePlane) +
                                            cells.sorted.capacity() * sizeof(CellPair) * 2);

      // Work items: (cell, run of ≤ chunk pixels) — cells hold from one to thousands of samples.
      struct Item {
        uint32_t cell, begin, end;
      };
      std::vector<Item> items;
      for (uint32_t c = 0; c < static_cast<uint32_t>(cam.cell_count()); ++c) {
        const uint32_t pb = cells.begin[c], pe = cells.end[c];
        if (pb == pe) continue;
        const uint64_t nt = table.end[c] - table.begin[c];
        ++nonempty_cells;
        sum_tris += nt;
        sum_samples += pe - pb;
        tris_max = std::max<uint64_t>(tris_max, nt);
        samples_max = std::max<uint64_t>(samples_max, pe - pb);
        // Long lists (dense models: cells holding thousands of triangles) get longer items: each
        // item gathers its cell's depth-cut prefix once, and there the gather is what grows; the
        // sample groups keep the per-pixel scans of a long item short (elephant 512²: ×2 −20 %
        // CPU; ×4 with groups of 8 reads 1.99 M list entries instead of 3.37 M).
        const uint32_t step = nt > kLongCellList ? opt_.long_chunk * opt_.chunk : opt_.chunk;
        for (uint32_t b = pb; b < pe; b += step) items.push_back({c, b, std::min(pe, b + step)});
      }

      t0 = std::chrono::steady_clock::now();
      tbb::parallel_for(
          tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
            Scratch& sc = scratch.local();
            sc.light_uv.resize(n);
            sc.su.resize(n);
            sc.sv.resize(n);
            sc.cover.resize(words + 1);
            sc.blocked.resize(words + 1);
            uint64_t l_grid = 0, l_read = 0, l_item = 0, l_group = 0, l_scanned = 0, l_tested = 0,
                     l_volume = 0, l_hidden = 0, l_necessary = 0, l_full = 0;
            for (size_t it = r.begin(); it != r.end(); ++it) {
              const Item& item = items[it];
              // Samples are sorted by depth within the cell, so an item spans few depths.
              const int m = static_cast<int>(item.end - item.begin);
              sc.ix.resize(m), sc.iy.resize(m), sc.iz.resize(m), sc.outside.resize(m);
              for (int i = 0; i < m; ++i) {
                const Vec3& q = p_light[cells.sorted[item.begin + i].item];
                sc.ix[i] = q.x, sc.iy[i] = q.y, sc.iz[i] = cells.sample_z[item.begin + i];
              }
              const ItemBounds bounds =
                  item_bounds(flat, sc.ix.data(), sc.iy.data(), sc.iz.data(), m);
              sc.batch.gather(packed.data(), planes.data(),
                              table.pairs.data() + table.begin[item.cell],
                              table.pairs.data() + table.end[item.cell], bounds);
              if (solids.count() > 0 && sc.batch.count > 0) {
                // Which solids each sample is outside of; the faces all of them see from behind.
                SampleBox item_box{Vec3(kInfinity), Vec3(-kInfinity), ~uint64_t{0}};
                for (int i = 0; i < m; ++i) {
                  const Vec3& q = p_light[cells.sorted[item.begin + i].item];
                  sc.outside[i] = solids.outside(q);
                  item_box.lo = glm::min(item_box.lo, q), item_box.hi = glm::max(item_box.hi, q);
                  item_box.outside &= sc.outside[i];
                }
                sc.batch.drop_solid_back_faces(item_box);
              } else {
                std::fill(sc.outside.begin(), sc.outside.end(), uint64_t{0});
              }
              l_read += sc.batch.read;
              l_grid +=
                  uint64_t{table.end[item.cell] - table.begin[item.cell]} * (item.end - item.begin);
              if (sc.batch.count == 0) {
                // Nothing can block any of the item's samples (most of a frame's pixels): their
                // masks stay zero, and only semi-opaque scenes shade here.
                if (any_translucent) {
                  sc.trans.assign(n, 1.0f);
                  for (int i = 0; i < m; ++i) {
                    const uint32_t pix = active[cells.sorted[item.begin + i].item];
                    shade(pix, masks.pixel(pix), sc.trans.data(), sc);
                  }
                }
                continue;
              }
              // The item's samples in groups close in slab coordinates, each culling the item's
              // candidates with its own bounds before its samples' per-pixel culls scan them.
              group_samples(flat, sc.ix.data(), sc.iy.data(), sc.iz.data(), m,
                            opt_.pixel_cull ? opt_.group : 0, sc.group_order, sc.group_ends);
              for (size_t gi = 0, g0 = 0; gi < sc.group_ends.size(); g0 = sc.group_ends[gi++]) {
                const int g1 = sc.group_ends[gi];
                const CandidateBatch* from = &sc.batch;
                if (sc.group_ends.size() > 1) {
                  const int gm = g1 - static_cast<int>(g0);
                  sc.gx.resize(gm), sc.gy.resize(gm), sc.gz.resize(gm), sc.gp.resize(gm);
                  uint64_t outside = ~uint64_t{0};
                  for (int j = 0; j < gm; ++j) {
                    const int i = sc.group_order[g0 + j];
                    sc.gx[j] = sc.ix[i], sc.gy[j] = sc.iy[i], sc.gz[j] = sc.iz[i];
                    sc.gp[j] = p_light[cells.sorted[item.begin + i].item];
                    outside &= sc.outside[i];
                  }
                  sc.group_batch.narrow(
                      sc.batch, item_bounds(flat, sc.gx.data(), sc.gy.data(), sc.gz.data(), gm),
                      sc.gp.data(), gm, solids.count() > 0 ? outside : 0);
                  from = &sc.group_batch;
                }
                l_group += uint64_t(from->count) * (g1 - g0);
                for (size_t oi = g0; oi < static_cast<size_t>(g1); ++oi) {
                  const uint32_t e = item.begin + sc.group_order[oi];
                  const uint32_t a = cells.sorted[e].item;
                  const uint32_t pix = active[a];
                  const Vec3 p = p_light[a];
                  l_item += sc.batch.count;
                  // This pixel's light: constant frames are the light space's own unit square.
                  PixelLight pl;
                  pl.p = p;
                  pl.w = -p;
                  LightFrame frame = frame0;
                  if (point) {
                    pl.axis_aligned = false;
                    pl.eu = pl.ev = Vec3(0.0f);
                  } else if (sphere) {
                    frame = light_frame(light, g.shadow_origin(pix));
                    pl.axis_aligned = false;
                    pl.w = space.to_light(frame.corner) - p;
                    auto dir = [&](const Vec3& d) {
                      return Vec3(glm::dot(space.inv_u, d), glm::dot(space.inv_v, d),
                                  glm::dot(space.inv_n, d));
                    };
                    pl.eu = dir(frame.edge_u);
                    pl.ev = dir(frame.edge_v);
                  }
                  const Vec2* uv = shared.data();
                  Vec2 lo = uv_lo, hi = uv_hi;
                  int ns = point ? 1 : n;
                  if (per_pixel_samples) {
                    ctx.samples.pixel_samples(static_cast<int>(pix % g.width),
                                              static_cast<int>(pix / g.width), sc.light_uv);
                    uv = sc.light_uv.data();
                    lo = Vec2(kInfinity), hi = Vec2(-kInfinity);
                    for (int s = 0; s < n; ++s) lo = glm::min(lo, uv[s]), hi = glm::max(hi, uv[s]);
                  }
                  if (point) lo = hi = Vec2(0.0f);
                  // Sample coordinates as arrays (per-sample rasterizer, alpha): shared ones are
                  // split once per frame.
                  const float* su = shared_u.data();
                  const float* sv = shared_v.data();
                  if (per_pixel_samples || point) {
                    for (int s = 0; s < ns; ++s)
                      sc.su[s] = point ? 0.0f : uv[s].x, sc.sv[s] = point ? 0.0f : uv[s].y;
                    su = sc.su.data(), sv = sc.sv.data();
                  }

                  // Emitting samples (round lights): blocking bits are only kept for those.
                  std::vector<uint64_t> emit_dyn;
                  const uint64_t* em = emit_words.data();
                  if (per_pixel_samples || point) {
                    emit_dyn.assign(words, 0);
                    for (int s = 0; s < ns; ++s)
                      if (point || frame.emits(uv[s])) emit_dyn[s >> 6] |= uint64_t{1} << (s & 63);
                    em = emit_dyn.data();
                  }
                  const int nw = (ns + 63) / 64;
                  std::fill(sc.blocked.begin(), sc.blocked.end(), 0);
                  std::fill(std::begin(sc.rows), std::end(sc.rows), 0u);
                  bool any_blocked = false;  // some bit of sc.rows is set
                  // Per-sample transmittance (semi-opaque occluders only), shaded with this pixel.
                  float* tr = nullptr;
                  if (any_translucent) {
                    sc.trans.assign(n, 1.0f);
                    tr = sc.trans.data();
                  }
                  const uint32_t full_row = k >= 32 ? ~0u : (1u << k) - 1u;

                  auto fully_blocked = [&]() {
                    if (use_rows) {
                      if (emit_count == n) {
                        uint32_t all = full_row;
                        for (int j = 0; j < k; ++j) all &= sc.rows[j];
                        return all == full_row;
                      }
                      std::vector<uint64_t> tmp(words, 0);
                      rows_to_words(sc.rows, k, tmp.data());
                      for (int i = 0; i < words; ++i)
                        if ((tmp[i] & em[i]) != em[i]) return false;
                      return true;
                    }
                    for (int i = 0; i < nw; ++i)
                      if ((sc.blocked[i] & em[i]) != em[i]) return false;
                    return true;
                  };

                  // Rasterizes a batch of candidates into the pixel's bits; true once every
                  // emitting sample is blocked (opaque).
                  auto rasterize = [&](const CandidateBatch& cb) {
                    for (int first = 0; first < cb.count; first += kLanes) {
                      uint32_t surv =
                          setup_batch(cb, first, pl, lo, hi, use_rows ? k : 0, sc.lines);
                      l_tested += std::min(kLanes, cb.count - first);
                      l_volume += std::popcount(surv);
                      if (use_rows && any_blocked && opt_.hidden_cull) {
                        // Shadows wholly inside samples already blocked add nothing.
                        const uint32_t hid = hidden_lanes(sc.lines.cells, surv, sc.rows);
                        l_hidden += std::popcount(hid);
                        surv &= ~hid;
                      }
                      bool changed = false;
                      if (use_rows) {
                        // Opaque triangles straight into the pixel's rows; the others (alpha,
                        // semi-opaque) one by one below.
                        const uint32_t opaque = surv & cb.opaque_lanes(first);
                        const uint32_t hit = raster_rows_or(sc.lines, opaque, k, sc.rows);
                        l_necessary += std::popcount(hit);
                        changed |= hit != 0;
                        surv &= ~opaque;
                      }
                      while (surv) {
                        const int lane = std::countr_zero(surv);
                        surv &= surv - 1;
                        const uint32_t tri = cb.tri[first + lane];
                        bool covered;
                        if (use_rows) {
                          covered = raster_rows(sc.lines, lane, k, sc.tri_rows) != 0;
                          if (covered && (soup.opaque[tri] == 0)) {
                            std::fill(sc.cover.begin(), sc.cover.end(), 0);
                            rows_to_words(sc.tri_rows, k, sc.cover.data());
                          }
                        } else if (use_lut) {
                          const uint64_t* m0 = lut->lookup(sc.lines.a[0][lane], sc.lines.b[0][lane],
                                                           sc.lines.c[0][lane]);
                          const uint64_t* m1 = lut->lookup(sc.lines.a[1][lane], sc.lines.b[1][lane],
                                                           sc.lines.c[1][lane]);
                          const uint64_t* m2 = lut->lookup(sc.lines.a[2][lane], sc.lines.b[2][lane],
                                                           sc.lines.c[2][lane]);
                          const uint64_t* m3 = lut->lookup(sc.lines.a[3][lane], sc.lines.b[3][lane],
                                                           sc.lines.c[3][lane]);
                          uint64_t any = 0;
                          for (int i = 0; i < words; ++i)
                            any |= sc.cover[i] = m0[i] & m1[i] & m2[i] & m3[i];
                          covered = any != 0;
                        } else {
                          covered = raster_samples(sc.lines, lane, su, sv, ns, sc.cover.data());
                        }
                        if (!covered) continue;
                        ++l_necessary;
                        if (soup.opaque[tri]) {
                          if (use_rows) {
                            // Whole 16-row registers (raster_rows zero-fills up to them).
                            for (int jb = 0; jb < k; jb += kLanes)
                              for (int j = jb; j < jb + kLanes; ++j) sc.rows[j] |= sc.tri_rows[j];
                          } else {
                            for (int i = 0; i < nw; ++i) sc.blocked[i] |= sc.cover[i];
                          }
                          changed = true;
                          continue;
                        }
                        // Alpha-textured or semi-opaque: the texture decides per covered sample, at
                        // the barycentrics of that sample's ray (as the Embree occlusion filter
                        // does).
                        const Mesh& mesh = ctx.scene.meshes[soup.mesh[tri]];
                        const Material& mat = ctx.scene.material_of(mesh);
                        const Texture* alpha = mat.alpha_texture >= 0
                                                   ? &ctx.scene.textures[mat.alpha_texture]
                                                   : nullptr;
                        for (int i = 0; i < nw; ++i) {
                          uint64_t bits = sc.cover[i];
                          while (bits) {
                            const int s = 64 * i + std::countr_zero(bits);
                            bits &= bits - 1;
                            if (alpha) {
                              const Vec2 bc = hit_barycentrics(sc.lines, lane, su[s], sv[s]);
                              if (alpha->sample_scalar(mesh.uv_at(soup.prim[tri], bc.x, bc.y)) <
                                  kAlphaCutoff)
                                continue;
                            }
                            if (mat.transmittance > 0.0f) {
                              tr[s] *= mat.transmittance;
                            } else if (use_rows) {
                              sc.rows[s / k] |= 1u << (s % k);
                              changed = true;
                            } else {
                              sc.blocked[s >> 6] |= uint64_t{1} << (s & 63);
                              changed = true;
                            }
                          }
                        }
                      }
                      any_blocked |= changed;
                      if (changed && fully_blocked()) {
                        ++l_full;
                        return true;
                      }
                    }
                    return false;
                  };
                  bool done = false;
                  if (opt_.pixel_cull) {
                    // The item's candidates culled with the pixel's own bounds (an item spans a
                    // cell's worth of directions, a pixel one) and the separating plane, in chunks
                    // so that a full mask stops the cull as well.
                    const float pz = cells.sample_z[e];
                    const ItemBounds own = item_bounds(flat, &p.x, &p.y, &pz, 1);
                    constexpr int kChunk = 8 * kLanes;
                    const ShadowBoxCull box{lo, hi, use_rows ? k : 0};
                    const ShadowBoxCull* box_cull = pl.axis_aligned ? &box : nullptr;
                    const uint64_t outside = sc.outside[sc.group_order[oi]];
                    // The item batch is in depth order: this pixel's depth cut is a prefix of it
                    // (samples nearer than the item's deepest skip the tail).
                    const int scan_end = from->depth_prefix(own.zmax);
                    // Its chunks deepest first (deepest_first), each scanned to the end unless
                    // the mask fills.
                    const int chunks = (scan_end + kChunk - 1) / kChunk;
                    for (int step = 0; step < chunks && !done; ++step) {
                      const int c0 = deepest_first ? std::max(0, scan_end - (step + 1) * kChunk)
                                                   : step * kChunk;
                      const int c1 = deepest_first ? scan_end - step * kChunk
                                                   : std::min(scan_end, c0 + kChunk);
                      // With the mask so far: shadows inside blocked samples are not set up.
                      const bool hide = use_rows && any_blocked && opt_.hidden_cull;
                      l_scanned += c1 - c0;
                      sc.pixel_batch.keep(*from, c0, c1, own, p, box_cull, hide ? sc.rows : nullptr,
                                          outside);
                      done = rasterize(sc.pixel_batch);
                    }
                  } else {
                    done = rasterize(sc.batch);
                  }
                  uint64_t* out = masks.pixel(pix);
                  if (shade_in_place) {
                    sc.own.assign(words, 0);
                    out = sc.own.data();
                  }
                  if (use_rows) {
                    rows_to_words(sc.rows, k, out);
                  } else if (point) {
                    if (sc.blocked[0] & 1u)
                      for (int s = 0; s < n; ++s) out[s >> 6] |= uint64_t{1} << (s & 63);
                  } else {
                    for (int i = 0; i < nw; ++i) out[i] = sc.blocked[i];
                  }
                  if (point && tr)
                    for (int s = 1; s < n; ++s) tr[s] = tr[0];
                  // Only emitting samples carry bits (SampleMasks convention).
                  if (!point)
                    for (int i = 0; i < words; ++i) out[i] &= em[i];
                  if (tr || shade_in_place) shade(pix, out, tr, sc);
                }
              }
            }
            from_grid += l_grid;
            item_kept += l_item;
            group_kept += l_group;
            hidden += l_hidden;
            pixel_scanned += l_scanned;
            gathered += l_read;
            tested += l_tested;
            in_volume += l_volume;
            necessary += l_necessary;
            early_full += l_full;
          });
      raster_ms += elapsed_ms(t0);
    }
    wait_for_solids();  // when no pass ran
    vis.times.add("project_pixels", project_ms);
    vis.times.add("count_prefix_sum", astats.count_ms + astats.prefix_ms);
    vis.times.add("write_pairs", astats.write_ms);
    vis.times.add("sort_pairs", astats.sort_ms);
    vis.times.add("bitmask_rasterization", raster_ms);

    // ---- Step 5: V per pixel, weighted exactly as raytrace weights its rays. Scenes with
    // semi-opaque occluders shade inside the work item (above), while the pixel's transmittances
    // are in the thread's scratch: memory per work item, not frame × samples. Without the
    // frame's masks, every pixel a pass reached was shaded there and the others keep V = 1.
    t0 = std::chrono::steady_clock::now();
    if (!shade_in_place)
      parallel_chunks(active.size(), 1024, [&](size_t b, size_t e) {
        Scratch& sc = scratch.local();
        for (size_t a = b; a < e; ++a) {
          if (!any_translucent) {
            shade(active[a], masks.pixel(active[a]), nullptr, sc);
          } else if (!may_be_shadowed[a]) {  // the grid passes shaded the others
            sc.trans.assign(n, 1.0f);
            shade(active[a], masks.pixel(active[a]), sc.trans.data(), sc);
          }
        }
      });
    vis.times.add("shading", elapsed_ms(t0));

    Counters& c = vis.counters;
    c["triangles"] = static_cast<double>(tri_count);
    c["active_pixels"] = static_cast<double>(active.size());
    c["back_facing_skipped"] = static_cast<double>(back_facing);
    // Active pixels no shadow-casting mesh's box can shadow: not in the grid passes.
    c["pixels_box_culled"] = static_cast<double>(box_culled);
    c["solids"] = static_cast<double>(solids.count());  // closed components culled by side
    // Wall time finding them took, beside the stages before the first pass (whose times include
    // it wherever it held a core; `find_solids_wait` is what the pass then waited for).
    c["find_solids_ms"] = solids_ms;
    c["pairs"] = static_cast<double>(astats.pairs);
    c["pairs_without_retraction"] = static_cast<double>(astats.pairs_without_retraction);
    c["aabb_cells"] = static_cast<double>(astats.aabb_cells);
    c["culled_behind_light"] = static_cast<double>(astats.culled_behind_light);
    c["culled_beyond_samples"] = static_cast<double>(astats.culled_beyond_samples);
    c["straddling_light"] = static_cast<double>(astats.straddling_light);
    c["cells_with_samples"] = static_cast<double>(nonempty_cells);
    c["triangles_per_cell_max"] = static_cast<double>(tris_max);
    c["triangles_per_cell_avg"] =
        nonempty_cells ? static_cast<double>(sum_tris) / nonempty_cells : 0.0;
    c["samples_per_cell_max"] = static_cast<double>(samples_max);
    c["samples_per_cell_avg"] =
        nonempty_cells ? static_cast<double>(sum_samples) / nonempty_cells : 0.0;
    c["assignments_grid"] = static_cast<double>(from_grid.load());  // the paper's per-cell lists
    c["gather_reads"] = static_cast<double>(gathered.load());  // list entries read per work item
    c["assignments_item"] = static_cast<double>(item_kept.load());  // after the per-item cull
    // After the per-group cull (× the group's samples); equals assignments_item without groups.
    c["assignments_group"] = static_cast<double>(group_kept.load());
    // Item candidates the per-pixel cull scanned: of each pixel's depth-cut prefix of its item's,
    // the chunks it read before its mask filled.
    c["pixel_cull_reads"] = static_cast<double>(pixel_scanned.load());
    c["assignments_total"] =
        static_cast<double>(tested.load());  // set up: after the per-pixel cull
    c["assignments_in_volume"] = static_cast<double>(in_volume.load());
    c["assignments_necessary"] = static_cast<double>(necessary.load());
    // In the volume, but their shadow box held only samples already blocked: not rasterized.
    c["assignments_hidden"] = static_cast<double>(hidden.load());
    c["pixels_early_full"] = static_cast<double>(early_full.load());
    c["memory_bytes"] = static_cast<double>(
        peak_bytes + masks.words_per_pixel() * 8.0 * g.pixel_count() +
        (any_translucent ? scratch.size() * n * sizeof(float) : 0) + (lut ? lut->bytes() : 0));
    c["rasterizer"] = use_rows ? 0.0 : (use_lut ? 1.0 : 2.0);  // 0 row spans, 1 LUT, 2 per sample
    if (ctx.want_masks) vis.masks = std::move(masks);
    return vis;
  }

 private:
  Options opt_;
};

}  // namespace

void register_gears(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "gears";
  info.summary =
      "GEARS: per-pixel sets of potentially blocking triangles, rasterized onto light-sample "
      "bitmasks";
  info.reference = "[Wang 2014 §3, §4.2, §4.3]";
  info.sample_exact = true;
  info.options = {
      {"grid",
       OptionType::integer,
       "0",
       "grid resolution (cells per side) of the triangle→pixel assignment; 0: one cell per 8×8 "
       "image pixels (max(width, height) / 8, at least 16)",
       {},
       0,
       2048},
      {"variant",
       OptionType::choice,
       "edge",
       "bitmask rasterization: edge planes (exact) or the 2D LUT (§4.3, approximate)",
       {"edge", "lut"}},
      {"lut_resolution",
       OptionType::integer,
       "256",
       "LUT bins per axis (line direction × offset)",
       {},
       4,
       4096},
      {"retraction",
       OptionType::boolean,
       "true",
       "extrude shadow volumes only to the deepest sample of the touched cells (§3.1)",
       {},
       0,
       1},
      {"cell_depth_cull",
       OptionType::boolean,
       "true",
       "skip cells whose deepest sample is nearer than the triangle",
       {},
       0,
       1},
      {"eye_distance",
       OptionType::real,
       "1.0",
       "grid-camera eye distance behind the light, in light diagonals",
       {},
       0.01,
       1000},
      {"chunk",
       OptionType::integer,
       "32",
       "pixels per parallel work item within a cell",
       {},
       1,
       1 << 20},
      {"pixel_cull",
       OptionType::boolean,
       "true",
       "re-cull each pixel's candidates (slabs, depth, separating plane) before the setup",
       {},
       0,
       1},
      {"group",
       OptionType::integer,
       "8",
       "samples per group within a work item: each group culls the item's candidates with its own "
       "slabs before the per-pixel cull (0: off)",
       {},
       0,
       1 << 20},
      {"hidden_cull",
       OptionType::boolean,
       "true",
       "skip a triangle whose shadow box holds only samples already blocked in the pixel's mask",
       {},
       0,
       1},
      {"deepest_first",
       OptionType::boolean,
       "true",
       "each pixel takes its candidates nearest to itself first, so that umbrae fill early and "
       "what lies behind them is hidden (same masks; semi-opaque occluders keep the list's order)",
       {},
       0,
       1},
      {"box_cull",
       OptionType::boolean,
       "true",
       "leave out of the grid the pixels no shadow-casting mesh's bounding box can shadow",
       {},
       0,
       1},
      {"solid_cull",
       OptionType::boolean,
       "true",
       "drop the faces of closed opaque meshes that a sample outside their box sees from behind",
       {},
       0,
       1},
      {"long_chunk",
       OptionType::integer,
       "4",
       "work items of cells whose list holds over 2048 triangles: this many times `chunk` samples",
       {},
       1,
       64},
  };
  info.create = [](const MethodOptions& o) {
    Options opt;
    opt.grid = o.get_int("grid");
    opt.lut = o.get_choice("variant") == "lut";
    opt.lut_resolution = o.get_int("lut_resolution");
    opt.assign.retraction = o.get_bool("retraction");
    opt.assign.cell_depth_cull = o.get_bool("cell_depth_cull");
    opt.eye_distance = static_cast<float>(o.get_real("eye_distance"));
    opt.chunk = o.get_int("chunk");
    opt.pixel_cull = o.get_bool("pixel_cull");
    opt.group = o.get_int("group");
    opt.long_chunk = o.get_int("long_chunk");
    opt.hidden_cull = o.get_bool("hidden_cull");
    opt.deepest_first = o.get_bool("deepest_first");
    opt.box_cull = o.get_bool("box_cull");
    opt.solid_cull = o.get_bool("solid_cull");
    return std::make_unique<Gears>(opt);
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
