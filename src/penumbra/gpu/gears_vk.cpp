// `gears` on Vulkan: the pipeline of [Wang 2014 §4.2] in compute shaders, on the frame's G-buffer
// and light samples (uploaded once per light):
//   host:  light space and the grid camera C (gears::make_light_space / make_grid_camera, the CPU
//          method's own construction; a finer default grid than the CPU's); per side, the
//          triangles in the CPU's depth order with the CPU's per-pixel cull data;
//   GPU:   pixel → cell (gears_cells), triangle → cells count (gears_count), exclusive prefix sum,
//          write of the (cell, triangle) pairs (gears_write), radix sort by cell (radix_*),
//          begin/end per cell (gears_ranges), per-pixel edge-plane rasterization onto the k×k
//          bitmask, one 32-bit word per row (gears_raster) or sample by sample, or by the LUT
//          [Wang 2014 §4.3] (gears_samples), after the CPU's per-pixel culls; semi-opaque
//          occluders scale per-sample transmittances instead of setting bits;
//   host:  the masks read back into SampleMasks and weighted exactly as the CPU gears does.
// Three submissions per side of the light plane: the pair count is read back to size the pair
// buffers, and the longest cell to size the rasterization's chunks. The host's part is in
// gears_vk_host.cpp.
#include <algorithm>
#include <bit>
#include <deque>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/gears_vk_host.hpp"
#include "penumbra/gpu/sort.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/solids.hpp"

namespace penumbra::gpu {

namespace {

using namespace gears_host;  // the host's part (gears_vk_host.hpp)

// shaders/gears.glsl's GridCamera (scalar layout: every member 4-byte aligned).
struct GridCameraGpu {
  float eye[3];
  float plane_z;
  float grid_lo[2];
  float cell_scale[2];
  int32_t res_x, res_y;
  float far_z, light_max_z, light_min_z;
  int32_t corner_count;
  float side;
  float pad;
  float corners[8][4];
};
static_assert(sizeof(GridCameraGpu) == 64 + 128);

struct CellsPush {
  VkDeviceAddress cam, pix, cell, cell_max_z;
  uint32_t n;
};
struct CountPush {
  VkDeviceAddress cam, tris, counts, rects, overflow, cell_max_z, zmin;
  uint32_t n;
};
struct WritePush {
  VkDeviceAddress rects, offsets, keys, vals, cell_max_z, zmin;
  uint32_t n, res_x;
  float light_max_z;
};
struct RangesPush {
  VkDeviceAddress keys, begin, end;
  uint32_t n;
};
struct LongestPush {
  VkDeviceAddress begin, end, longest;
  uint32_t n;
};
struct RasterPush {
  VkDeviceAddress pix, tris, cell, begin, end, vals, rows_out, emit_rows;
  uint32_t n;
  int32_t k;
  uint32_t first, chunk;  // this dispatch's part of each cell's list
  float uv_lo[2], uv_hi[2];
  VkDeviceAddress alpha, texels, samples;
  uint32_t flags;  // 2: deepest first, 4: the pixel's culls, 8: the hidden-shadow test
};
static_assert(sizeof(RasterPush) == 128);
struct SamplesPush {
  VkDeviceAddress pix, tris, cell, begin, end, vals, words_out, emit, samples, alpha, texels;
  uint32_t n, ns, words, first, chunk;
  uint32_t flags;  // 1: per-pixel samples, 2: deepest first, 4: the pixel's culls
  float uv_lo[2], uv_hi[2];
};
static_assert(sizeof(SamplesPush) == 128);

// Triangles of a cell one rasterization dispatch walks: × 32 rows × 4 lines below llvmpipe's
// 65535-iteration loop limit (gears_raster.comp), and still few dispatches on a real GPU.
constexpr uint32_t kRasterChunk = 256;
/// The same with alpha-tested or semi-opaque triangles, whose covered samples are visited one by
/// one (up to k per row).
uint32_t rows_chunk(int k, bool translucent) {
  if (!translucent) return kRasterChunk;
  return std::clamp<uint32_t>(50000u / static_cast<uint32_t>(k * k + k + 1), 1, kRasterChunk);
}
/// The same for the per-sample rasterizer (gears_samples.comp): one iteration per sample.
uint32_t samples_chunk(int samples) {
  return std::clamp<uint32_t>(50000u / static_cast<uint32_t>(samples + 8), 1, kRasterChunk);
}

/// The grid's resolution: the option's, or by default one cell per 2×2 image pixels (the CPU's
/// default is one per 8×8). Each GPU pixel walks its whole cell list (the CPU's work items first
/// cull it for their ≤ 32 samples), so shorter lists pay for the extra pairs: lavapipe, bunny
/// 128², 16×16 samples: rasterization 9–10 s on 16² cells, 2.3 s on 64². At most 255 per side,
/// so that the count pass's loop over a triangle's cells stays below llvmpipe's loop limit.
constexpr int kMaxCpuDeviceGrid = 255;
int grid_resolution_vk(int option, int width, int height) {
  if (option > 0) return option;
  return std::clamp((std::max(width, height) + 1) / 2, 16, kMaxCpuDeviceGrid);
}

/// What the rasterization passes read and write (device addresses) and how they walk.
struct RasterInputs {
  VkDeviceAddress pix, tris, cell, begin, end, vals, rows, emit, samples, alpha, texels;
  uint32_t na;
  Vec2 uv_lo, uv_hi;
  bool deepest_first, pixel_cull, hidden_cull, translucent;
};

/// The rasterization of every pixel's cell list, in chunks of the longest list (llvmpipe's loop
/// limit): row spans (gears_raster) or sample by sample (gears_samples), as `plan` says.
void record_rasterization(Programs& programs, CommandList& raster, const Plan& plan,
                          const RasterInputs& in, uint32_t longest) {
  const uint32_t culls = (in.deepest_first ? 2u : 0u) | (in.pixel_cull ? 4u : 0u);
  if (!plan.use_rows) {
    const uint32_t chunk = samples_chunk(plan.ns);
    for (uint32_t first = 0; first < longest; first += chunk) {
      const SamplesPush sp{in.pix,
                           in.tris,
                           in.cell,
                           in.begin,
                           in.end,
                           in.vals,
                           in.rows,
                           in.emit,
                           in.samples,
                           in.alpha,
                           in.texels,
                           in.na,
                           static_cast<uint32_t>(plan.ns),
                           plan.words,
                           first,
                           chunk,
                           (plan.per_pixel || plan.point ? 1u : 0u) | culls,
                           {in.uv_lo.x, in.uv_lo.y},
                           {in.uv_hi.x, in.uv_hi.y}};
      raster.dispatch(programs.get(Shader::gears_samples), sp, in.na);
      raster.barrier();
    }
    return;
  }
  const uint32_t chunk = rows_chunk(plan.k, in.translucent);
  for (uint32_t first = 0; first < longest; first += chunk) {
    const RasterPush rp{in.pix,
                        in.tris,
                        in.cell,
                        in.begin,
                        in.end,
                        in.vals,
                        in.rows,
                        in.emit,
                        in.na,
                        plan.k,
                        first,
                        chunk,
                        {in.uv_lo.x, in.uv_lo.y},
                        {in.uv_hi.x, in.uv_hi.y},
                        in.alpha,
                        in.texels,
                        in.samples,
                        culls | (in.hidden_cull ? 8u : 0u)};
    raster.dispatch(programs.get(Shader::gears_raster), rp, in.na);
    raster.barrier();
  }
}

/// The device buffers both sides share: emitting samples, alpha texels, sample positions, each
/// pixel's cell, the masks (then, for semi-opaque occluders, each pixel's per-sample
/// transmittances, in the same buffer since the shaders' push constants are full), and the
/// per-triangle scratch of the count and pair passes.
struct FrameBuffers {
  Buffer emit, texels, samples, cell, rows, counts, rects, zmin;
  Buffer totals;  // last count, last offset, Σcounts/1024
  size_t mask_words = 0, trans_words = 0;
};

FrameBuffers upload_frame(VulkanContext& vk, const Plan& plan, const HostFrame& h,
                          StageTimes& times) {
  ScopedStage stage(times, "wall_upload");
  const uint32_t na = static_cast<uint32_t>(h.active.size());
  const uint32_t tris = std::max<uint32_t>(h.tri_count, 1);
  FrameBuffers b;
  b.emit = plan.use_rows ? vk.upload(h.ss.emit_rows) : vk.upload(h.ss.emit_bits);
  b.texels = vk.upload(h.occ.texels);
  b.samples = vk.upload(h.ss.sample_uv);
  b.cell = Buffer(vk, std::max<size_t>(na, 1) * 4, Memory::device);
  const size_t words_per_pixel = plan.use_rows ? static_cast<size_t>(plan.k) : plan.words;
  b.mask_words = size_t{na} * words_per_pixel;
  b.trans_words = h.occ.semi_opaque ? size_t{na} * static_cast<size_t>(plan.ns) : 0;
  b.rows = Buffer(vk, std::max<size_t>(b.mask_words + b.trans_words, 1) * 4, Memory::device);
  b.counts = Buffer(vk, size_t{tris} * 4, Memory::device);
  b.rects = Buffer(vk, size_t{tris} * 16, Memory::device);
  b.zmin = Buffer(vk, size_t{tris} * 4, Memory::device);
  b.totals = Buffer(vk, 16, Memory::device);
  vk.submit_now([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, b.rows.handle(), 0, VK_WHOLE_SIZE, 0);
    if (b.trans_words > 0)
      vkCmdFillBuffer(cmd, b.rows.handle(), b.mask_words * 4, b.trans_words * 4,
                      std::bit_cast<uint32_t>(1.0f));
  });
  return b;
}

/// The grid camera as shaders/gears.glsl reads it.
GridCameraGpu camera_gpu(const gears::GridCamera& cam, int side) {
  GridCameraGpu cg{};
  cg.eye[0] = cam.eye.x, cg.eye[1] = cam.eye.y, cg.eye[2] = cam.eye.z;
  cg.plane_z = cam.plane_z;
  cg.grid_lo[0] = cam.grid_lo.x, cg.grid_lo[1] = cam.grid_lo.y;
  cg.cell_scale[0] = cam.cell_scale.x, cg.cell_scale[1] = cam.cell_scale.y;
  cg.res_x = cam.res_x, cg.res_y = cam.res_y;
  cg.far_z = cam.far_z, cg.light_max_z = cam.light_max_z, cg.light_min_z = cam.light_min_z;
  cg.corner_count = static_cast<int32_t>(cam.light_corners.size());
  cg.side = static_cast<float>(side);
  for (size_t c = 0; c < cam.light_corners.size() && c < 8; ++c)
    for (int d = 0; d < 3; ++d) cg.corners[c][d] = cam.light_corners[c][d];
  return cg;
}

/// One side's device inputs: its grid camera, the pixels with this side's slab bounds, the
/// triangles in this side's depth order with their cull data, and each cell's deepest sample.
struct SideInputs {
  gears::GridCamera cam;
  Buffer cam_buf, pix_buf, tri_buf, alpha_buf, cell_max_z;
  uint32_t cells = 0;
};

/// Submission 1: each pixel's cell, each triangle's cell count and their exclusive prefix sum.
/// Returns the pair count, read back to size the pair buffers.
uint32_t count_pairs(VulkanContext& vk, Programs& programs, const FrameBuffers& fb,
                     const SideInputs& si, uint32_t na, uint32_t tri_count,
                     std::deque<Buffer>& scratch, StageTimes& times) {
  CommandList cl(vk);
  cl.fill(fb.totals, 0);
  cl.fill(si.cell_max_z, 0);
  cl.barrier();
  cl.dispatch(programs.get(Shader::gears_cells),
              CellsPush{si.cam_buf.address(), si.pix_buf.address(), fb.cell.address(),
                        si.cell_max_z.address(), na},
              na);
  cl.barrier();
  cl.mark("pixel_cells");
  cl.dispatch(
      programs.get(Shader::gears_count),
      CountPush{si.cam_buf.address(), si.tri_buf.address(), fb.counts.address(), fb.rects.address(),
                fb.totals.address() + 8, si.cell_max_z.address(), fb.zmin.address(), tri_count},
      tri_count);
  cl.barrier();
  cl.copy(fb.counts, fb.totals, 4, size_t{tri_count - 1} * 4, 0);
  cl.barrier();
  cl.mark("triangle_count");
  record_exclusive_scan(programs, cl, fb.counts, tri_count, scratch);
  cl.copy(fb.counts, fb.totals, 4, size_t{tri_count - 1} * 4, 4);
  cl.barrier();
  cl.mark("prefix_sum");
  cl.submit(&times);
  const std::vector<uint32_t> tot = vk.download<uint32_t>(fb.totals, 3);
  if (uint64_t{tot[2]} * 1024 >= (uint64_t{1} << 31))
    throw Error("gears on vulkan: more than 2^31 triangle-cell pairs (lower gears.grid)");
  return tot[0] + tot[1];
}

/// Each cell's list of triangles: the (cell, triangle) pairs radix sorted by cell (stable, so
/// each list keeps the depth order), each cell's [begin, end) and the longest list's length.
struct CellLists {
  Buffer keys, vals, keys_tmp, vals_tmp, begin, end;
  bool in_place = true;  // the sorted pairs are in keys/vals, else in keys_tmp/vals_tmp
  uint32_t longest = 0;
  const Buffer& sorted_vals() const { return in_place ? vals : vals_tmp; }
};

/// Submission 2: the pairs, their sort by cell and the per-cell ranges [Wang 2014 §4.2]; the
/// longest list is read back to size the rasterization's chunks.
CellLists sort_pairs(VulkanContext& vk, Programs& programs, const FrameBuffers& fb,
                     const SideInputs& si, uint32_t pairs, uint32_t tri_count,
                     std::deque<Buffer>& scratch, StageTimes& times) {
  CellLists lists;
  lists.keys = Buffer(vk, size_t{pairs} * 4, Memory::device);
  lists.vals = Buffer(vk, size_t{pairs} * 4, Memory::device);
  lists.keys_tmp = Buffer(vk, size_t{pairs} * 4, Memory::device);
  lists.vals_tmp = Buffer(vk, size_t{pairs} * 4, Memory::device);
  lists.begin = Buffer(vk, size_t{si.cells} * 4, Memory::device);
  lists.end = Buffer(vk, size_t{si.cells} * 4, Memory::device);
  CommandList cl(vk);
  cl.dispatch(programs.get(Shader::gears_write),
              WritePush{fb.rects.address(), fb.counts.address(), lists.keys.address(),
                        lists.vals.address(), si.cell_max_z.address(), fb.zmin.address(), tri_count,
                        static_cast<uint32_t>(si.cam.res_x), si.cam.light_max_z},
              tri_count);
  cl.barrier();
  cl.mark("pair_write");
  const int key_bits = std::max(1, static_cast<int>(std::bit_width(si.cells - 1)));
  lists.in_place = record_radix_sort(programs, cl, lists.keys, lists.vals, lists.keys_tmp,
                                     lists.vals_tmp, pairs, key_bits, scratch);
  const Buffer& sorted_keys = lists.in_place ? lists.keys : lists.keys_tmp;
  cl.mark("radix_sort");
  cl.fill(lists.begin, 0);
  cl.fill(lists.end, 0);
  cl.barrier();
  cl.dispatch(programs.get(Shader::gears_ranges),
              RangesPush{sorted_keys.address(), lists.begin.address(), lists.end.address(), pairs},
              pairs);
  cl.barrier();
  cl.fill(fb.totals, 0);
  cl.barrier();
  cl.dispatch(
      programs.get(Shader::gears_longest),
      LongestPush{lists.begin.address(), lists.end.address(), fb.totals.address(), si.cells},
      si.cells);
  cl.barrier();
  cl.mark("cell_ranges");
  cl.submit(&times);
  lists.longest = vk.download<uint32_t>(fb.totals, 1)[0];
  return lists;
}

class GearsVk final : public ShadowMethod {
 public:
  GearsVk(Backend& backend, const MethodOptions& o) : backend_(backend) {
    lut_ = o.get_choice("variant") == "lut";
    lut_resolution_ = o.get_int("lut_resolution");
    grid_ = o.get_int("grid");
    deepest_first_ = o.get_bool("deepest_first");
    pixel_cull_ = o.get_bool("pixel_cull");
    solid_cull_ = o.get_bool("solid_cull");
    hidden_cull_ = o.get_bool("hidden_cull");
    eye_distance_ = static_cast<float>(o.get_real("eye_distance"));
  }

  /// The closed components of the scene's opaque meshes, as the CPU's prepare.
  void prepare(const Scene& scene) override {
    if (!solid_cull_) return;
    components_ = gears::find_closed_components(scene);
    prepared_ = true;
  }

  Visibility compute(const ShadowContext& ctx) override {
    VulkanContext& vk = backend_.context();
    const GBuffer& g = ctx.gbuffer;
    const Plan plan = plan_of(ctx, lut_);
    // A triangle's count and pair passes loop over its cells: up to grid² iterations, which
    // llvmpipe would cut short (and drop pairs) past its 65535-iteration limit.
    if (vk.info().type == "cpu" && grid_ > kMaxCpuDeviceGrid)
      throw Error("gears on vulkan: gears.grid " + std::to_string(grid_) + " exceeds " +
                  std::to_string(kMaxCpuDeviceGrid) + " on " + vk.device_name() +
                  " (a CPU device's shader loops are limited); lower it or use a GPU");

    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    if (plan.emission) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));
    SampleMasks masks(g.width, g.height, plan.n);
    HostFrame h = host_setup(ctx, plan, masks.words_per_pixel(), vis.times);
    const FrameBuffers fb = upload_frame(vk, plan, h, vis.times);

    // Both sides' submissions are one stage, added after both (after their GPU stages).
    StageTimes wall;
    uint64_t total_pairs = 0;
    for (int side : {+1, -1}) total_pairs += run_side(vk, ctx, plan, h, fb, side, vis.times, wall);
    vis.times.add("wall_gpu", wall.get("wall_gpu"));

    {  // Readback: the masks, and V weighted as on the CPU.
      ScopedStage stage(vis.times, "wall_readback");
      const std::vector<uint32_t> rows =
          vk.download<uint32_t>(fb.rows, fb.mask_words + fb.trans_words);
      read_back(ctx, plan, h.ss, h.active, rows, fb.mask_words, h.occ.semi_opaque, masks, vis);
    }
    vis.counters["triangles"] = h.tri_count;
    vis.counters["active_pixels"] = static_cast<double>(h.active.size());
    vis.counters["pairs"] = static_cast<double>(total_pairs);
    if (ctx.want_masks) vis.masks = std::move(masks);
    return vis;
  }

 private:
  /// Host setup, as the CPU gears: light space, per-pixel data, the occluders with the per-pixel
  /// culls' soup and solids, and the light samples (with the LUT [Wang 2014 §4.3]).
  HostFrame host_setup(const ShadowContext& ctx, const Plan& plan, int words64, StageTimes& times) {
    ScopedStage stage(times, "light_space_setup");
    HostFrame h;
    active_pixels_and_toward(ctx, plan, h);
    const gears::LightSpace space = gears::make_light_space(ctx.light, h.frame0, h.toward, +1);
    pixel_data(ctx, space, plan, h.active, h.p_light, h.pix);
    h.occ = gather_occluders(ctx.scene, space);
    h.tri_count = static_cast<uint32_t>(h.occ.tris.size() / 12);
    // The CPU's separating-plane and solid culls need its soup, and the solids each pixel is
    // certified outside of.
    if (pixel_cull_) h.soup = soup_of(h.occ);
    if (pixel_cull_ && solid_cull_) {
      if (!prepared_) prepare(ctx.scene);
      h.solids = gears::find_solids(components_, h.soup);
      mark_outside_solids(h);
    }
    h.r = plan.sphere ? ctx.light.radius / glm::length(space.axis_n) : 0.0f;
    h.corners = light_corners(plan, h.r);
    h.ss = sample_setup(ctx, plan, h.frame0, h.active, words64);
    if (plan.use_lut) append_lut(h.ss.shared, lut_resolution_, h.occ.texels);
    return h;
  }

  /// One side of the light plane (+1: the pixels in front of it; −1: those behind, z mirrored):
  /// its grid camera and inputs, then the three submissions. Returns its pair count; the
  /// submissions' wall time goes to `wall`.
  uint32_t run_side(VulkanContext& vk, const ShadowContext& ctx, const Plan& plan, HostFrame& h,
                    const FrameBuffers& fb, int side, StageTimes& times, StageTimes& wall) const {
    std::vector<Vec3> pts;
    for (const Vec3& q : h.p_light)
      if ((side > 0) == (q.z >= 0.0f)) pts.emplace_back(q.x, q.y, side * q.z);
    if (pts.empty() || h.tri_count == 0) return 0;
    const SideInputs si = side_inputs(vk, ctx, plan, h, side, pts, times);
    ScopedStage gpu(wall, "wall_gpu");
    Programs& programs = backend_.programs();
    const uint32_t na = static_cast<uint32_t>(h.active.size());
    std::deque<Buffer> scratch;
    const uint32_t pairs = count_pairs(vk, programs, fb, si, na, h.tri_count, scratch, times);
    if (pairs > 0) {
      const CellLists lists = sort_pairs(vk, programs, fb, si, pairs, h.tri_count, scratch, times);
      rasterize(vk, programs, plan, h, fb, si, lists, times);
    }
    return pairs;
  }

  /// One side's grid camera over `pts` (its pixels, z mirrored) and its device inputs; h.pix's
  /// slab bounds are this side's from here on.
  SideInputs side_inputs(VulkanContext& vk, const ShadowContext& ctx, const Plan& plan,
                         HostFrame& h, int side, const std::vector<Vec3>& pts,
                         StageTimes& times) const {
    ScopedStage stage(times, "grid_camera");
    SideInputs si;
    const gears::LightSpace side_space =
        gears::make_light_space(ctx.light, h.frame0, h.toward, side);
    si.cam =
        gears::make_grid_camera(side_space, h.corners, h.r, pts, eye_distance_,
                                grid_resolution_vk(grid_, ctx.gbuffer.width, ctx.gbuffer.height));
    const GridCameraGpu cg = camera_gpu(si.cam, side);
    si.cam_buf = vk.upload(&cg, sizeof(cg));
    const SideTriangles sorted = side_cull_data(
        si.cam, side, !plan.per_pixel && !plan.point && !plan.sphere, h.ss.uv_lo, h.ss.uv_hi,
        h.p_light, h.pix, h.occ, pixel_cull_ ? &h.soup : nullptr, h.solids);
    si.pix_buf = vk.upload(h.pix);
    si.tri_buf = vk.upload(sorted.tris);
    si.alpha_buf = vk.upload(sorted.alpha);
    si.cells = static_cast<uint32_t>(si.cam.cell_count());
    si.cell_max_z = Buffer(vk, size_t{si.cells} * 4, Memory::device);
    return si;
  }

  /// Submission 3: the rasterization of every pixel's cell list, in chunks of the longest.
  void rasterize(VulkanContext& vk, Programs& programs, const Plan& plan, const HostFrame& h,
                 const FrameBuffers& fb, const SideInputs& si, const CellLists& lists,
                 StageTimes& times) const {
    // An umbra's nearest layer to the pixel fills its mask early when taken first; semi-opaque
    // occluders keep the list's order, so that their products are formed in the CPU's order.
    const bool deepest_first = deepest_first_ && pixel_cull_ && !h.occ.semi_opaque;
    CommandList raster(vk);
    const RasterInputs in{si.pix_buf.address(),
                          si.tri_buf.address(),
                          fb.cell.address(),
                          lists.begin.address(),
                          lists.end.address(),
                          lists.sorted_vals().address(),
                          fb.rows.address(),
                          fb.emit.address(),
                          fb.samples.address(),
                          si.alpha_buf.address(),
                          fb.texels.address(),
                          static_cast<uint32_t>(h.active.size()),
                          h.ss.uv_lo,
                          h.ss.uv_hi,
                          deepest_first,
                          pixel_cull_,
                          pixel_cull_ && hidden_cull_,
                          h.occ.translucent};
    record_rasterization(programs, raster, plan, in, lists.longest);
    raster.mark("rasterize");
    raster.submit(&times);
  }
  Backend& backend_;
  int grid_ = 0;
  bool lut_ = false;
  int lut_resolution_ = 256;
  bool deepest_first_ = true;
  bool pixel_cull_ = true;
  bool solid_cull_ = true;
  bool hidden_cull_ = true;
  bool prepared_ = false;
  gears::SolidComponents components_;  // the scene's closed components (solid cull)
  float eye_distance_ = 1.0f;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_gears_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<GearsVk>(backend, options);
}

}  // namespace penumbra::gpu
