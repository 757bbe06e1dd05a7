#include "penumbra/shadows/gears/pixel_pass.hpp"

#include <algorithm>
#include <bit>

#include "penumbra/shadows/gears/lut.hpp"
#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra::gears {

FramePlan plan_frame(const ShadowContext& ctx, const Options& options, const LightSetup& setup,
                     const SharedSamples& samples) {
  FramePlan plan;
  plan.n = ctx.samples.count();
  plan.k = ctx.samples.k();
  plan.words = (plan.n + 63) / 64;
  plan.point = ctx.light.shape == LightShape::point;
  plan.sphere = ctx.light.shape == LightShape::sphere;
  plan.per_pixel_samples = ctx.samples.per_pixel();
  // Row spans need the regular grid (sample i in cell (i % k, i / k) at its centre); the LUT
  // needs shared positions; everything else tests sample by sample.
  const bool grid_pattern =
      ctx.samples.spec().pattern == SamplePattern::grid && !plan.per_pixel_samples;
  plan.use_lut = options.lut && !plan.per_pixel_samples && !plan.point;
  plan.use_rows = !plan.use_lut && grid_pattern && plan.k <= 32 && !plan.point;
  plan.simple_weights = !ctx.light.is_textured() && !plan.per_pixel_samples && !plan.point;
  // The frame's array holds the bits when they are asked for or when step 5 shades from them
  // (weighted lights, semi-opaque occluders); otherwise each pixel is shaded from its own bits at
  // once, and the pixels no pass reaches keep V = 1 (no bit set): no frame-size array to clear
  // (32 MB at 1024², k 16) nor to read.
  plan.shade_in_place =
      !ctx.want_masks && plan.simple_weights && !setup.any_translucent && samples.emit_count > 0;
  // An umbra's front layer then fills the mask early and what lies behind it is hidden (same
  // bits: the mask is the union of the covered samples). Semi-opaque occluders keep the list's
  // order, so that their transmittance products are formed in one order whatever the options.
  plan.deepest_first = options.deepest_first && !setup.any_semi_opaque;
  return plan;
}

RasterTally& RasterTally::operator+=(const RasterTally& o) {
  grid += o.grid, gathered += o.gathered, item += o.item, group += o.group;
  scanned += o.scanned, tested += o.tested, in_volume += o.in_volume, hidden += o.hidden;
  necessary += o.necessary, early_full += o.early_full;
  return *this;
}

void shade_pixel(const ShadowContext& ctx, const FramePlan& plan, const SharedSamples& samples,
                 uint32_t pixel, const uint64_t* mask, const float* transmittance, Scratch& scratch,
                 Visibility& out) {
  if (plan.simple_weights && !transmittance) {
    int blocked = 0;
    for (int i = 0; i < plan.words; ++i) blocked += std::popcount(mask[i] & samples.emit_words[i]);
    SampleWeights w;
    w.visible = Vec3(static_cast<float>(samples.emit_count - blocked));
    w.total = Vec3(static_cast<float>(samples.emit_count));
    out.lit[pixel] = w.visible_fraction();
    return;
  }
  const GBuffer& g = ctx.gbuffer;
  const LightFrame frame = light_frame(ctx.light, g.shadow_origin(pixel));
  const int n = plan.n;
  scratch.shade_uv.resize(n);
  scratch.vis.resize(n);
  ctx.samples.pixel_samples(static_cast<int>(pixel % g.width), static_cast<int>(pixel / g.width),
                            scratch.shade_uv);
  for (int s = 0; s < n; ++s) {
    const bool blocked = (mask[s >> 6] >> (s & 63)) & 1u;
    scratch.vis[s] = blocked ? 0.0f : (transmittance ? transmittance[s] : 1.0f);
  }
  const Texture* emission =
      ctx.light.is_textured() ? &ctx.scene.textures[ctx.light.emission_texture] : nullptr;
  const SampleWeights w =
      accumulate_sample_weights(frame, emission, ctx.light.radiance, scratch.shade_uv, scratch.vis);
  out.lit[pixel] = w.visible_fraction();
  if (emission) out.lit_rgb->operator[](pixel) = w.visible_fraction_rgb();
}

namespace {

/// One pixel's light-sample bitmask as its candidates are rasterized onto it: row spans
/// (use_rows) or 64-bit words, and per-sample transmittances for semi-opaque occluders.
class PixelMask {
 public:
  PixelMask(const SidePass& pass, uint32_t pixel, const Vec3& p_light, Scratch& scratch,
            RasterTally& tally);

  /// Rasterizes a batch of candidates into the bits; true once every emitting sample is blocked.
  bool add(const CandidateBatch& batch);
  /// Whether some bit is set (the row spans' hidden cull needs one).
  bool any_blocked() const { return any_blocked_; }
  const PixelLight& light() const { return light_; }
  Vec2 uv_lo() const { return uv_lo_; }
  Vec2 uv_hi() const { return uv_hi_; }
  /// Writes the bits (emitting samples only) and shades the pixel where the plan says so.
  void finish();

 private:
  bool fully_blocked();
  /// Opaque lanes' coverage into the mask; the others (alpha, semi-opaque) sample by sample.
  bool add_lane(const CandidateBatch& batch, int first, int lane);
  bool add_translucent(uint32_t tri, int lane);

  const SidePass& pass_;
  const FramePlan& plan_;
  Scratch& sc_;
  RasterTally& tally_;
  uint32_t pixel_;
  PixelLight light_;
  const Vec2* uv_ = nullptr;  // the pixel's sample positions
  const float* su_ = nullptr;
  const float* sv_ = nullptr;
  Vec2 uv_lo_, uv_hi_;
  int ns_ = 0;                    // samples tested (1 for a point light)
  const uint64_t* em_ = nullptr;  // emitting samples
  float* tr_ = nullptr;           // per-sample transmittance (semi-opaque occluders only)
  uint32_t full_row_ = 0;
  bool any_blocked_ = false;
};

PixelMask::PixelMask(const SidePass& pass, uint32_t pixel, const Vec3& p_light, Scratch& scratch,
                     RasterTally& tally)
    : pass_(pass), plan_(pass.plan), sc_(scratch), tally_(tally), pixel_(pixel) {
  const ShadowContext& ctx = pass.ctx;
  const GBuffer& g = ctx.gbuffer;
  const int n = plan_.n;
  // This pixel's light: constant frames are the light space's own unit square.
  light_.p = p_light;
  light_.w = -p_light;
  LightFrame frame = pass.setup.frame0;
  if (plan_.point) {
    light_.axis_aligned = false;
    light_.eu = light_.ev = Vec3(0.0f);
  } else if (plan_.sphere) {
    const LightSpace& space = pass.setup.space;
    frame = light_frame(ctx.light, g.shadow_origin(pixel));
    light_.axis_aligned = false;
    light_.w = space.to_light(frame.corner) - p_light;
    auto dir = [&](const Vec3& d) {
      return Vec3(glm::dot(space.inv_u, d), glm::dot(space.inv_v, d), glm::dot(space.inv_n, d));
    };
    light_.eu = dir(frame.edge_u);
    light_.ev = dir(frame.edge_v);
  }
  uv_ = pass.samples.uv.data();
  uv_lo_ = pass.samples.uv_lo, uv_hi_ = pass.samples.uv_hi;
  ns_ = plan_.point ? 1 : n;
  if (plan_.per_pixel_samples) {
    ctx.samples.pixel_samples(static_cast<int>(pixel % g.width), static_cast<int>(pixel / g.width),
                              sc_.light_uv);
    uv_ = sc_.light_uv.data();
    uv_lo_ = Vec2(kInfinity), uv_hi_ = Vec2(-kInfinity);
    for (int s = 0; s < n; ++s)
      uv_lo_ = glm::min(uv_lo_, uv_[s]), uv_hi_ = glm::max(uv_hi_, uv_[s]);
  }
  if (plan_.point) uv_lo_ = uv_hi_ = Vec2(0.0f);
  // Sample coordinates as arrays (per-sample rasterizer, alpha): shared ones are split once a
  // frame. Blocking bits are only kept for emitting samples (round lights).
  su_ = pass.samples.u.data(), sv_ = pass.samples.v.data();
  em_ = pass.samples.emit_words.data();
  if (plan_.per_pixel_samples || plan_.point) {
    sc_.emit.assign(plan_.words, 0);
    for (int s = 0; s < ns_; ++s) {
      sc_.su[s] = plan_.point ? 0.0f : uv_[s].x, sc_.sv[s] = plan_.point ? 0.0f : uv_[s].y;
      if (plan_.point || frame.emits(uv_[s])) sc_.emit[s >> 6] |= uint64_t{1} << (s & 63);
    }
    su_ = sc_.su.data(), sv_ = sc_.sv.data();
    em_ = sc_.emit.data();
  }
  std::fill(sc_.blocked.begin(), sc_.blocked.end(), 0);
  std::fill(std::begin(sc_.rows), std::end(sc_.rows), 0u);
  if (pass.setup.any_translucent) {
    sc_.trans.assign(n, 1.0f);
    tr_ = sc_.trans.data();
  }
  full_row_ = plan_.k >= 32 ? ~0u : (1u << plan_.k) - 1u;
}

bool PixelMask::fully_blocked() {
  const int words = plan_.words;
  if (plan_.use_rows) {
    if (pass_.samples.emit_count == plan_.n) {
      uint32_t all = full_row_;
      for (int j = 0; j < plan_.k; ++j) all &= sc_.rows[j];
      return all == full_row_;
    }
    sc_.words.assign(words, 0);
    rows_to_words(sc_.rows, plan_.k, sc_.words.data());
    for (int i = 0; i < words; ++i)
      if ((sc_.words[i] & em_[i]) != em_[i]) return false;
    return true;
  }
  for (int i = 0; i < (ns_ + 63) / 64; ++i)
    if ((sc_.blocked[i] & em_[i]) != em_[i]) return false;
  return true;
}

bool PixelMask::add(const CandidateBatch& cb) {
  const int k = plan_.k;
  const bool hidden_cull = plan_.use_rows && pass_.options.hidden_cull;
  for (int first = 0; first < cb.count; first += kLanes) {
    uint32_t surv =
        setup_batch(cb, first, light_, uv_lo_, uv_hi_, plan_.use_rows ? k : 0, sc_.lines);
    tally_.tested += std::min(kLanes, cb.count - first);
    tally_.in_volume += std::popcount(surv);
    if (hidden_cull && any_blocked_) {
      // Shadows wholly inside samples already blocked add nothing.
      const uint32_t hid = hidden_lanes(sc_.lines.cells, surv, sc_.rows);
      tally_.hidden += std::popcount(hid);
      surv &= ~hid;
    }
    bool changed = false;
    if (plan_.use_rows) {
      // Opaque triangles straight into the pixel's rows; the others one by one below.
      const uint32_t opaque = surv & cb.opaque_lanes(first);
      const uint32_t hit = raster_rows_or(sc_.lines, opaque, k, sc_.rows);
      tally_.necessary += std::popcount(hit);
      changed |= hit != 0;
      surv &= ~opaque;
    }
    while (surv) {
      const int lane = std::countr_zero(surv);
      surv &= surv - 1;
      changed |= add_lane(cb, first, lane);
    }
    any_blocked_ |= changed;
    if (changed && fully_blocked()) {
      ++tally_.early_full;
      return true;
    }
  }
  return false;
}

bool PixelMask::add_lane(const CandidateBatch& cb, int first, int lane) {
  const int k = plan_.k;
  const int nw = (ns_ + 63) / 64;
  const uint32_t tri = cb.tri[first + lane];
  const bool opaque = pass_.setup.soup.opaque[tri] != 0;
  bool covered;
  if (plan_.use_rows) {
    covered = raster_rows(sc_.lines, lane, k, sc_.tri_rows) != 0;
    if (covered && !opaque) {
      std::fill(sc_.cover.begin(), sc_.cover.end(), 0);
      rows_to_words(sc_.tri_rows, k, sc_.cover.data());
    }
  } else if (plan_.use_lut) {
    const LineBatch& l = sc_.lines;
    const uint64_t* m0 = pass_.lut->lookup(l.a[0][lane], l.b[0][lane], l.c[0][lane]);
    const uint64_t* m1 = pass_.lut->lookup(l.a[1][lane], l.b[1][lane], l.c[1][lane]);
    const uint64_t* m2 = pass_.lut->lookup(l.a[2][lane], l.b[2][lane], l.c[2][lane]);
    const uint64_t* m3 = pass_.lut->lookup(l.a[3][lane], l.b[3][lane], l.c[3][lane]);
    uint64_t any = 0;
    for (int i = 0; i < plan_.words; ++i) any |= sc_.cover[i] = m0[i] & m1[i] & m2[i] & m3[i];
    covered = any != 0;
  } else {
    covered = raster_samples(sc_.lines, lane, su_, sv_, ns_, sc_.cover.data());
  }
  if (!covered) return false;
  ++tally_.necessary;
  if (!opaque) return add_translucent(tri, lane);
  if (plan_.use_rows) {
    // Whole 16-row registers (raster_rows zero-fills up to them).
    for (int jb = 0; jb < k; jb += kLanes)
      for (int j = jb; j < jb + kLanes; ++j) sc_.rows[j] |= sc_.tri_rows[j];
  } else {
    for (int i = 0; i < nw; ++i) sc_.blocked[i] |= sc_.cover[i];
  }
  return true;
}

bool PixelMask::add_translucent(uint32_t tri, int lane) {
  // Alpha-textured or semi-opaque: the texture decides per covered sample, at the barycentrics of
  // that sample's ray (as the Embree occlusion filter does).
  const Scene& scene = pass_.ctx.scene;
  const TriangleSoup& soup = pass_.setup.soup;
  const Mesh& mesh = scene.meshes[soup.mesh[tri]];
  const Material& mat = scene.material_of(mesh);
  const Texture* alpha = mat.alpha_texture >= 0 ? &scene.textures[mat.alpha_texture] : nullptr;
  bool changed = false;
  for (int i = 0; i < (ns_ + 63) / 64; ++i) {
    uint64_t bits = sc_.cover[i];
    while (bits) {
      const int s = 64 * i + std::countr_zero(bits);
      bits &= bits - 1;
      if (alpha) {
        const Vec2 bc = hit_barycentrics(sc_.lines, lane, su_[s], sv_[s]);
        if (alpha->sample_scalar(mesh.uv_at(soup.prim[tri], bc.x, bc.y)) < kAlphaCutoff) continue;
      }
      if (mat.transmittance > 0.0f) {
        tr_[s] *= mat.transmittance;
      } else if (plan_.use_rows) {
        sc_.rows[s / plan_.k] |= 1u << (s % plan_.k);
        changed = true;
      } else {
        sc_.blocked[s >> 6] |= uint64_t{1} << (s & 63);
        changed = true;
      }
    }
  }
  return changed;
}

void PixelMask::finish() {
  const int n = plan_.n, words = plan_.words;
  uint64_t* out = plan_.shade_in_place ? nullptr : pass_.masks.pixel(pixel_);
  if (plan_.shade_in_place) {
    sc_.own.assign(words, 0);
    out = sc_.own.data();
  }
  if (plan_.use_rows) {
    rows_to_words(sc_.rows, plan_.k, out);
  } else if (plan_.point) {
    if (sc_.blocked[0] & 1u)
      for (int s = 0; s < n; ++s) out[s >> 6] |= uint64_t{1} << (s & 63);
  } else {
    for (int i = 0; i < (ns_ + 63) / 64; ++i) out[i] = sc_.blocked[i];
  }
  if (plan_.point && tr_)
    for (int s = 1; s < n; ++s) tr_[s] = tr_[0];
  // Only emitting samples carry bits (SampleMasks convention).
  if (!plan_.point)
    for (int i = 0; i < words; ++i) out[i] &= em_[i];
  if (tr_ || plan_.shade_in_place)
    shade_pixel(pass_.ctx, plan_, pass_.samples, pixel_, out, tr_, sc_, pass_.out);
}

/// One pixel of a work item: its candidates (`from`, the item's or its group's) culled with its
/// own bounds, rasterized, then written or shaded. `e`: its entry in PixelCells::sorted.
void rasterize_pixel(const SidePass& pass, const CandidateBatch& from, uint32_t e, uint64_t outside,
                     Scratch& sc, RasterTally& tally) {
  const uint32_t a = pass.cells.sorted[e].item;
  const Vec3 p = pass.setup.p_light[a];
  PixelMask mask(pass, pass.setup.active[a], p, sc, tally);
  bool done = false;
  if (pass.options.pixel_cull) {
    // The item's candidates culled with the pixel's own bounds (an item spans a cell's worth of
    // directions, a pixel one) and the separating plane, in chunks so that a full mask stops the
    // cull as well.
    const float pz = pass.cells.sample_z[e];
    const ItemBounds own = item_bounds(pass.flat, &p.x, &p.y, &pz, 1);
    constexpr int kChunk = 8 * kLanes;
    const ShadowBoxCull box{mask.uv_lo(), mask.uv_hi(), pass.plan.use_rows ? pass.plan.k : 0};
    const ShadowBoxCull* box_cull = mask.light().axis_aligned ? &box : nullptr;
    // The item batch is in depth order: this pixel's depth cut is a prefix of it (samples nearer
    // than the item's deepest skip the tail). Its chunks are taken deepest first
    // (deepest_first), each scanned to the end unless the mask fills.
    const int scan_end = from.depth_prefix(own.zmax);
    const int chunks = (scan_end + kChunk - 1) / kChunk;
    const bool deepest_first = pass.plan.deepest_first;
    for (int step = 0; step < chunks && !done; ++step) {
      const int c0 = deepest_first ? std::max(0, scan_end - (step + 1) * kChunk) : step * kChunk;
      const int c1 = deepest_first ? scan_end - step * kChunk : std::min(scan_end, c0 + kChunk);
      // With the mask so far: shadows inside blocked samples are not set up.
      const bool hide = pass.plan.use_rows && mask.any_blocked() && pass.options.hidden_cull;
      tally.scanned += c1 - c0;
      sc.pixel_batch.keep(from, c0, c1, own, p, box_cull, hide ? sc.rows : nullptr, outside);
      done = mask.add(sc.pixel_batch);
    }
  } else {
    done = mask.add(sc.batch);
  }
  mask.finish();
}

/// The item's candidates from its cell's list (per-item cull), minus the faces of solids that
/// all its samples see from behind; fills the item's sample arrays and their solids.
void gather_item(const SidePass& pass, const WorkItem& item, Scratch& sc, RasterTally& tally) {
  const int m = static_cast<int>(item.end - item.begin);
  const auto& sorted = pass.cells.sorted;
  sc.ix.resize(m), sc.iy.resize(m), sc.iz.resize(m), sc.outside.resize(m);
  for (int i = 0; i < m; ++i) {
    const Vec3& q = pass.setup.p_light[sorted[item.begin + i].item];
    sc.ix[i] = q.x, sc.iy[i] = q.y, sc.iz[i] = pass.cells.sample_z[item.begin + i];
  }
  const ItemBounds bounds = item_bounds(pass.flat, sc.ix.data(), sc.iy.data(), sc.iz.data(), m);
  const CellPair* list = pass.table.pairs.data();
  sc.batch.gather(pass.packed, pass.planes, list + pass.table.begin[item.cell],
                  list + pass.table.end[item.cell], bounds);
  if (pass.solids.count() > 0 && sc.batch.count > 0) {
    // Which solids each sample is outside of; the faces all of them see from behind.
    SampleBox item_box{Vec3(kInfinity), Vec3(-kInfinity), ~uint64_t{0}};
    for (int i = 0; i < m; ++i) {
      const Vec3& q = pass.setup.p_light[sorted[item.begin + i].item];
      sc.outside[i] = pass.solids.outside(q);
      item_box.lo = glm::min(item_box.lo, q), item_box.hi = glm::max(item_box.hi, q);
      item_box.outside &= sc.outside[i];
    }
    sc.batch.drop_solid_back_faces(item_box);
  } else {
    std::fill(sc.outside.begin(), sc.outside.end(), uint64_t{0});
  }
  tally.gathered += sc.batch.read;
  tally.grid += uint64_t{pass.table.end[item.cell] - pass.table.begin[item.cell]} * m;
}

/// The candidates of the item's group [g0, g1) of samples (in group_order): the item's, culled
/// with the group's own bounds, when the item has several groups.
const CandidateBatch& group_candidates(const SidePass& pass, const WorkItem& item, int g0, int g1,
                                       Scratch& sc) {
  if (sc.group_ends.size() <= 1) return sc.batch;
  const int gm = g1 - g0;
  sc.gx.resize(gm), sc.gy.resize(gm), sc.gz.resize(gm), sc.gp.resize(gm);
  uint64_t outside = ~uint64_t{0};
  for (int j = 0; j < gm; ++j) {
    const int i = sc.group_order[g0 + j];
    sc.gx[j] = sc.ix[i], sc.gy[j] = sc.iy[i], sc.gz[j] = sc.iz[i];
    sc.gp[j] = pass.setup.p_light[pass.cells.sorted[item.begin + i].item];
    outside &= sc.outside[i];
  }
  sc.group_batch.narrow(sc.batch,
                        item_bounds(pass.flat, sc.gx.data(), sc.gy.data(), sc.gz.data(), gm),
                        sc.gp.data(), gm, pass.solids.count() > 0 ? outside : 0);
  return sc.group_batch;
}

}  // namespace

void rasterize_item(const SidePass& pass, const WorkItem& item, Scratch& sc, RasterTally& tally) {
  const FramePlan& plan = pass.plan;
  sc.light_uv.resize(plan.n);
  sc.su.resize(plan.n);
  sc.sv.resize(plan.n);
  sc.cover.resize(plan.words + 1);
  sc.blocked.resize(plan.words + 1);
  gather_item(pass, item, sc, tally);
  const int m = static_cast<int>(item.end - item.begin);
  if (sc.batch.count == 0) {
    // Nothing can block any of the item's samples (most of a frame's pixels): their masks stay
    // zero, and only semi-opaque scenes shade here.
    if (pass.setup.any_translucent) {
      sc.trans.assign(plan.n, 1.0f);
      for (int i = 0; i < m; ++i) {
        const uint32_t pix = pass.setup.active[pass.cells.sorted[item.begin + i].item];
        shade_pixel(pass.ctx, plan, pass.samples, pix, pass.masks.pixel(pix), sc.trans.data(), sc,
                    pass.out);
      }
    }
    return;
  }
  // The item's samples in groups close in slab coordinates, each culling the item's candidates
  // with its own bounds before its samples' per-pixel culls scan them.
  group_samples(pass.flat, sc.ix.data(), sc.iy.data(), sc.iz.data(), m,
                pass.options.pixel_cull ? pass.options.group : 0, sc.group_order, sc.group_ends);
  for (size_t gi = 0, g0 = 0; gi < sc.group_ends.size(); g0 = sc.group_ends[gi++]) {
    const int g1 = sc.group_ends[gi];
    const CandidateBatch& from = group_candidates(pass, item, static_cast<int>(g0), g1, sc);
    tally.group += uint64_t(from.count) * (g1 - g0);
    for (size_t oi = g0; oi < static_cast<size_t>(g1); ++oi) {
      tally.item += sc.batch.count;
      rasterize_pixel(pass, from, item.begin + sc.group_order[oi], sc.outside[sc.group_order[oi]],
                      sc, tally);
    }
  }
}

}  // namespace penumbra::gears
