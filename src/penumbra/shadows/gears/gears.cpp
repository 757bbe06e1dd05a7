// `gears`: exact soft shadows from per-pixel sets of potentially blocking triangles [Wang 2014 §3,
// §4.2] on the CPU. Steps: (3.1) grid camera C over the pixel samples; (3.2) samples → cells;
// (3.3) triangles → cells through their projected shadow volumes, with the retraction; (4) per
// pixel, the candidate triangles of its cell rasterized onto the k×k light-sample bitmask by edge
// planes (batched SIMD setup, row spans) or by the LUT [§4.3]; (5) V from the bits, weighted by
// light_weights.hpp exactly as `raytrace` weights its rays.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "penumbra/core/parallel.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/frame_setup.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/lut.hpp"
#include "penumbra/shadows/gears/pixel_pass.hpp"
#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

using namespace gears;

/// Cell lists longer than this get work items of `long_chunk` × `chunk` samples.
constexpr uint64_t kLongCellList = 2048;

/// What the grid passes add up, for the counters.
struct PassTotals {
  AssignStats assign;
  RasterTally raster;
  uint64_t nonempty_cells = 0, sum_tris = 0, sum_samples = 0, tris_max = 0, samples_max = 0;
  size_t peak_bytes = 0;
};

/// Work items: (cell, run of ≤ chunk samples) — cells hold from one to thousands of samples.
/// Long lists (dense models: cells holding thousands of triangles) get longer items: each item
/// gathers its cell's depth-cut prefix once, and there the gather is what grows; the sample groups
/// keep the per-pixel scans of a long item short (elephant 512²: ×2 −20 % CPU; ×4 with groups of
/// 8 reads 1.99 M list entries instead of 3.37 M).
std::vector<WorkItem> make_work_items(const Options& opt, const GridCamera& cam,
                                      const PixelCells& cells, const CellTriangles& table,
                                      PassTotals& totals) {
  std::vector<WorkItem> items;
  for (uint32_t c = 0; c < static_cast<uint32_t>(cam.cell_count()); ++c) {
    const uint32_t pb = cells.begin[c], pe = cells.end[c];
    if (pb == pe) continue;
    const uint64_t nt = table.end[c] - table.begin[c];
    ++totals.nonempty_cells;
    totals.sum_tris += nt;
    totals.sum_samples += pe - pb;
    totals.tris_max = std::max<uint64_t>(totals.tris_max, nt);
    totals.samples_max = std::max<uint64_t>(totals.samples_max, pe - pb);
    const uint32_t step = nt > kLongCellList ? opt.long_chunk * opt.chunk : opt.chunk;
    for (uint32_t b = pb; b < pe; b += step) items.push_back({c, b, std::min(pe, b + step)});
  }
  return items;
}

class Gears final : public ShadowMethod {
 public:
  explicit Gears(const Options& o) : opt_(o) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    if (ctx.light.is_textured()) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));

    // Steps 2/3.2 prologue: the pixel samples and the occluders in light space.
    ScopedStage setup_stage(vis.times, "light_space_setup");
    const LightSetup setup = setup_light_space(ctx);
    setup_stage.stop();
    // The solids are first needed to pack the triangles: found meanwhile, as one task (the pixel
    // and grid set-up below leave cores idle part of the time).
    Solids solids;
    double solids_ms = 0.0;
    tbb::task_group solids_task;
    if (opt_.solid_cull)
      solids_task.run([&] {
        const auto start = std::chrono::steady_clock::now();
        solids = find_solids(ctx.scene, setup.soup);
        solids_ms = elapsed_ms(start);
      });
    bool solids_ready = !opt_.solid_cull;
    auto wait_for_solids = [&] {
      if (solids_ready) return;
      ScopedStage wait(vis.times, "find_solids_wait");
      solids_task.wait();
      solids_ready = true;
    };

    const SharedSamples samples = shared_samples(ctx, setup);
    ScopedStage box_stage(vis.times, "pixel_box_cull");
    const std::vector<uint8_t> may_be_shadowed =
        box_cull_pixels(ctx, setup, samples, opt_.box_cull);
    box_stage.stop();
    const FramePlan plan = plan_frame(ctx, opt_, setup, samples);
    std::unique_ptr<EdgeLut> lut;
    if (plan.use_lut)
      lut = std::make_unique<EdgeLut>(samples.uv, opt_.lut_resolution, opt_.lut_resolution);
    SampleMasks masks;
    if (!plan.shade_in_place) masks = SampleMasks(g.width, g.height, plan.n);

    PassTotals totals;
    tbb::enumerable_thread_specific<Scratch> scratch;
    // One grid pass per side of the light plane that has samples.
    for (int side : {+1, -1}) {
      PassInputs in{ctx, setup, samples, plan, may_be_shadowed, solids, lut.get(), masks, vis};
      run_side(in, side, wait_for_solids, scratch, totals);
    }
    wait_for_solids();  // when no pass ran

    // Step 5: V per pixel, weighted exactly as raytrace weights its rays. Scenes with semi-opaque
    // occluders shade inside the work item, while the pixel's transmittances are in the thread's
    // scratch: memory per work item, not frame × samples. Without the frame's masks, every pixel a
    // pass reached was shaded there and the others keep V = 1.
    ScopedStage shading_stage(vis.times, "shading");
    if (!plan.shade_in_place) shade_frame(ctx, setup, samples, plan, may_be_shadowed, masks, vis);
    shading_stage.stop();

    write_counters(setup, solids, solids_ms, may_be_shadowed, totals, vis.counters);
    vis.counters["memory_bytes"] =
        static_cast<double>(totals.peak_bytes + masks.words_per_pixel() * 8.0 * g.pixel_count() +
                            (setup.any_translucent ? scratch.size() * plan.n * sizeof(float) : 0) +
                            (lut ? lut->bytes() : 0));
    vis.counters["rasterizer"] = plan.use_rows ? 0.0 : (plan.use_lut ? 1.0 : 2.0);
    if (ctx.want_masks) vis.masks = std::move(masks);
    return vis;
  }

 private:
  /// The frame's inputs of one grid pass.
  struct PassInputs {
    const ShadowContext& ctx;
    const LightSetup& setup;
    const SharedSamples& samples;
    const FramePlan& plan;
    const std::vector<uint8_t>& may_be_shadowed;
    const Solids& solids;
    const EdgeLut* lut;
    SampleMasks& masks;
    Visibility& vis;
  };

  /// Steps 3.1–4 for the samples on one side of the light plane: the grid camera over them, the
  /// samples and triangles bucketed by cell, and the work items rasterized.
  template <class WaitForSolids>
  void run_side(const PassInputs& in, int side, WaitForSolids& wait_for_solids,
                tbb::enumerable_thread_specific<Scratch>& scratch, PassTotals& totals) const {
    const LightSetup& setup = in.setup;
    const std::vector<Vec3>& p_light = setup.p_light;
    ScopedStage project_stage(in.vis.times, "project_pixels");
    // The grid spans every sample of the side (its cells then do not depend on the box cull);
    // only the samples that may be shadowed are bucketed.
    auto on_side = [&](size_t a) { return (side > 0) == (p_light[a].z >= 0.0f); };
    const std::vector<uint32_t> ids = parallel_indices(
        p_light.size(), [&](size_t a) { return in.may_be_shadowed[a] && on_side(a); });
    if (ids.empty()) return;
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
    if (!all_front) side_copy = mirrored(parallel_indices(p_light.size(), on_side));
    const GridCamera cam = make_grid_camera(
        make_light_space(in.ctx.light, setup.frame0, setup.toward, side), in.samples.corners,
        in.samples.light_max_z, all_front ? p_light : side_copy, opt_.eye_distance,
        grid_resolution(opt_.grid, in.ctx.gbuffer.width, in.ctx.gbuffer.height));
    side_copy = {};
    const PixelCells cells = bucket_pixels(cam, ids, pts);
    project_stage.stop();

    const AssignStats before = totals.assign;
    const CellTriangles table =
        assign_triangles(cam, setup.soup, side, cells, opt_.assign, totals.assign);
    const AssignStats& after = totals.assign;
    in.vis.times.add("count_prefix_sum",
                     after.count_ms + after.prefix_ms - before.count_ms - before.prefix_ms);
    in.vis.times.add("write_pairs", after.write_ms - before.write_ms);
    in.vis.times.add("sort_pairs", after.sort_ms - before.sort_ms);
    FlatLight flat = flat_light(cam);
    if (!in.plan.per_pixel_samples && !in.plan.point && !in.plan.sphere)
      flat = shrink_to_samples(flat, in.samples.uv_lo, in.samples.uv_hi);
    wait_for_solids();
    UninitVector<PackedTriangle> packed = pack_triangles(setup.soup, side, table.zmin, flat);
    if (in.solids.count() > 0)
      for (size_t t = 0; t < setup.soup.size(); ++t) packed[t].solid = in.solids.of_triangle[t];
    const UninitVector<TrianglePlane> planes =
        triangle_planes(setup.soup, plane_test_corners(flat, cam));
    totals.peak_bytes =
        std::max(totals.peak_bytes, table.bytes() + packed.size() * sizeof(PackedTriangle) +
                                        planes.size() * sizeof(TrianglePlane) +
                                        cells.sorted.capacity() * sizeof(CellPair) * 2);
    const std::vector<WorkItem> items = make_work_items(opt_, cam, cells, table, totals);

    ScopedStage raster_stage(in.vis.times, "bitmask_rasterization");
    const SidePass pass{in.ctx, opt_,  in.plan, setup,         in.samples,    in.solids, in.lut,
                        cells,  table, flat,    packed.data(), planes.data(), in.masks,  in.vis};
    tbb::enumerable_thread_specific<RasterTally> tallies;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        Scratch& sc = scratch.local();
                        RasterTally& tally = tallies.local();
                        for (size_t it = r.begin(); it != r.end(); ++it)
                          rasterize_item(pass, items[it], sc, tally);
                      });
    for (const RasterTally& t : tallies) totals.raster += t;
  }

  /// Step 5 for the pixels the passes did not shade (shade_in_place off).
  static void shade_frame(const ShadowContext& ctx, const LightSetup& setup,
                          const SharedSamples& samples, const FramePlan& plan,
                          const std::vector<uint8_t>& may_be_shadowed, const SampleMasks& masks,
                          Visibility& vis) {
    tbb::enumerable_thread_specific<Scratch> scratch;
    parallel_chunks(setup.active.size(), 1024, [&](size_t b, size_t e) {
      Scratch& sc = scratch.local();
      for (size_t a = b; a < e; ++a) {
        const uint32_t pix = setup.active[a];
        if (!setup.any_translucent) {
          shade_pixel(ctx, plan, samples, pix, masks.pixel(pix), nullptr, sc, vis);
        } else if (!may_be_shadowed[a]) {  // the grid passes shaded the others
          sc.trans.assign(plan.n, 1.0f);
          shade_pixel(ctx, plan, samples, pix, masks.pixel(pix), sc.trans.data(), sc, vis);
        }
      }
    });
  }

  static void write_counters(const LightSetup& setup, const Solids& solids, double solids_ms,
                             const std::vector<uint8_t>& may_be_shadowed, const PassTotals& t,
                             Counters& c) {
    const AssignStats& as = t.assign;
    const RasterTally& r = t.raster;
    c["triangles"] = static_cast<double>(setup.soup.size());
    c["active_pixels"] = static_cast<double>(setup.active.size());
    c["back_facing_skipped"] = static_cast<double>(setup.back_facing);
    // Active pixels no shadow-casting mesh's box can shadow: not in the grid passes.
    c["pixels_box_culled"] =
        static_cast<double>(std::count(may_be_shadowed.begin(), may_be_shadowed.end(), 0));
    c["solids"] = static_cast<double>(solids.count());  // closed components culled by side
    // Wall time finding them took, beside the stages before the first pass (whose times include
    // it wherever it held a core; `find_solids_wait` is what the pass then waited for).
    c["find_solids_ms"] = solids_ms;
    c["pairs"] = static_cast<double>(as.pairs);
    c["pairs_without_retraction"] = static_cast<double>(as.pairs_without_retraction);
    c["aabb_cells"] = static_cast<double>(as.aabb_cells);
    c["culled_behind_light"] = static_cast<double>(as.culled_behind_light);
    c["culled_beyond_samples"] = static_cast<double>(as.culled_beyond_samples);
    c["straddling_light"] = static_cast<double>(as.straddling_light);
    c["cells_with_samples"] = static_cast<double>(t.nonempty_cells);
    c["triangles_per_cell_max"] = static_cast<double>(t.tris_max);
    c["triangles_per_cell_avg"] =
        t.nonempty_cells ? static_cast<double>(t.sum_tris) / t.nonempty_cells : 0.0;
    c["samples_per_cell_max"] = static_cast<double>(t.samples_max);
    c["samples_per_cell_avg"] =
        t.nonempty_cells ? static_cast<double>(t.sum_samples) / t.nonempty_cells : 0.0;
    c["assignments_grid"] = static_cast<double>(r.grid);  // the paper's per-cell lists
    c["gather_reads"] = static_cast<double>(r.gathered);  // list entries read per work item
    c["assignments_item"] = static_cast<double>(r.item);  // after the per-item cull
    // After the per-group cull (× the group's samples); equals assignments_item without groups.
    c["assignments_group"] = static_cast<double>(r.group);
    // Item candidates the per-pixel cull scanned: of each pixel's depth-cut prefix of its item's,
    // the chunks it read before its mask filled.
    c["pixel_cull_reads"] = static_cast<double>(r.scanned);
    c["assignments_total"] = static_cast<double>(r.tested);  // set up: after the per-pixel cull
    c["assignments_in_volume"] = static_cast<double>(r.in_volume);
    c["assignments_necessary"] = static_cast<double>(r.necessary);
    // In the volume, but their shadow box held only samples already blocked: not rasterized.
    c["assignments_hidden"] = static_cast<double>(r.hidden);
    c["pixels_early_full"] = static_cast<double>(r.early_full);
  }

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
