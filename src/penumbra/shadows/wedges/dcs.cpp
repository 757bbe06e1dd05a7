#include "penumbra/shadows/wedges/dcs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/dcs_counters.hpp"
#include "penumbra/shadows/wedges/dcs_frame.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "penumbra/shadows/wedges/stsv.hpp"
#include "penumbra/shadows/wedges/stsv_lookup.hpp"
#include "penumbra/shadows/wedges/wedges.hpp"

namespace penumbra {

namespace {

using namespace wedge_pass;

using dcs::LayerClass;

/// Per tile row: counters of the sampling pass (summed at the end, deterministic).
struct RowStats {
  uint64_t edge_pixel_pairs = 0;  // (pixel, edge) pairs whose projection covers the light
  uint64_t covered_updates = 0;   // counter updates (samples covered, summed over edges)
  uint64_t sample_tests = 0;      // samples tested (n per pair)
  uint64_t straddle_weights = 0;  // per-receiver multiplicities evaluated
  uint64_t penumbra_pixels = 0;   // pixels with at least one covered edge
  uint64_t umbra_early_outs = 0;  // pixels whose centre count exceeds every possible decrement
  uint64_t wide_counters = 0;     // pixels whose bound needed int32 counters
  uint64_t max_edges = 0;
  uint64_t block_entries = 0;  // bin entries kept per 4×4 pixel block
  int32_t d_min = std::numeric_limits<int32_t>::max(), d_max = std::numeric_limits<int32_t>::min();
  PassCounters pass;
  stsv::StsvStats stsv;
  double stsv_ms = 0.0;  // thread time in the S-triangles' part of the sampling (pairs, lookups)
};

struct CoveredEdge {
  dcs::CoveredRegion region;
  int delta = 0;
  uint16_t layer_class = 0;
};

/// An S-triangle whose volume holds the pixel [Forest 2008 §5.1.3], with its J (§5.1.4).
struct StsvPair {
  stsv::Pair pair;
  uint32_t triangle = 0;
};

/// What one pixel's evaluation needs; thread-local, sized to the sample count.
struct Scratch {
  std::vector<Vec2> uv;
  dcs::SampleSet samples;  // per-pixel patterns
  std::vector<float> vis;
  std::vector<int16_t> c16;
  std::vector<int32_t> c32;
  std::vector<CoveredEdge> covered;
  std::vector<StsvPair> pairs;
  std::vector<uint8_t> flags;  // per sample: its segment crosses the S-triangle
  std::vector<int> abs_sum;    // per class: Σ |step| of the covered edges
  std::vector<int> stsv_sum;   // per class: S-triangles holding the pixel (each adds ≤ 1)
  void resize(int n, size_t classes) {
    abs_sum.assign(classes, 0);
    stsv_sum.assign(classes, 0);
    flags.resize(n);
    uv.resize(n);
    vis.resize(n);
    c16.resize(n * classes);
    c32.resize(n * classes);
  }
};

class Sampler {
 public:
  Sampler(const ShadowContext& ctx, const DcsOptions& options,
          const std::vector<LayerClass>& classes, const dcs::EdgeSet& edges, const BinnedWedges* bw,
          const stsv::StsvSet& stsv, Visibility& out)
      : ctx_(ctx),
        options_(options),
        classes_(classes),
        edges_(edges),
        bw_(bw),
        stsv_(stsv),
        out_(out),
        n_(ctx.samples.count()),
        emission_(ctx.light.is_textured() ? &emission_texture(ctx.scene, ctx.light, "dcs")
                                          : nullptr),
        round_(ctx.light.shape == LightShape::disk || ctx.light.shape == LightShape::sphere) {
    if (!ctx.samples.per_pixel())
      shared_.assign(ctx.samples.shared_samples(), ctx.samples.k(),
                     [&](const Vec2& uv) { return emits(uv); });
  }

  /// V of pixel i; pl null when no wedge or S-triangle of its tile can hold it (or it lies in the
  /// light plane). `weights`: BlockWeights of `bin` (needed when pl is not null); `stsv_bin`: the
  /// S-triangles of its tile.
  float shade(size_t i, const PixelLight* pl, const std::vector<uint32_t>& bin,
              dcs::BlockWeights* weights, const std::vector<uint32_t>& stsv_bin, RowStats& st) {
    thread_local Scratch sc;
    sc.resize(n_, classes_.size());
    const int width = ctx_.gbuffer.width;
    const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
    const dcs::SampleSet* samples = &shared_;
    if (ctx_.samples.per_pixel()) {
      ctx_.samples.pixel_samples(x, y, sc.uv);
      sc.samples.assign(sc.uv, ctx_.samples.k(), [&](const Vec2& uv) { return emits(uv); });
      samples = &sc.samples;
    }
    const dcs::SampleSet& ss = *samples;

    // The edges whose projection from p cuts the light, with their signed per-sample step.
    sc.covered.clear();
    std::vector<int>& abs_sum = sc.abs_sum;
    if (pl) {
      // The receiver's weights first: two plane tests per entry, and zero for most (pixel,
      // straddling edge) pairs (the edge is no silhouette from p), which then skip the wedge test
      // and the clip.
      weights->evaluate(edges_, bin, bw_->group, pl->point());
      st.straddle_weights += bin.size();
      for (size_t j = 0; j < bin.size(); ++j) {
        const int32_t m = weights->m[j];
        if (m == 0) continue;
        const uint32_t k = bin[j];
        const Wedge& w = bw_->wedges[k];
        const dcs::Edge& e = edges_.edges[bw_->group[k]];  // wedge k's edge
        ++st.pass.tests;
        if (!w.contains(pl->point())) continue;
        ++st.pass.inside;
        DVec2 a, b;
        if (!pl->clip(w, a, b)) continue;
        CoveredEdge ce;
        int turn = 0;
        if (!dcs::covered_region(a, b, ce.region, turn)) continue;
        ++st.pass.covered;
        // The wedges' sign [wedges/pass.hpp PixelLight::occlusion]: −τ · m · turn.
        ce.delta = -static_cast<int>(pl->tau()) * m * turn;
        ce.layer_class = e.layer_class;
        abs_sum[e.layer_class] += std::abs(ce.delta);
        sc.covered.push_back(ce);
      }
    }
    const size_t ncov = sc.covered.size();
    st.max_edges = std::max<uint64_t>(st.max_edges, ncov);
    if (ncov > 0) ++st.penumbra_pixels;
    st.edge_pixel_pairs += ncov;

    const int32_t d0 = classes_[0].centre_counts[i];
    // Umbra early-out: no sequence of the covered edges can bring an opaque count to 0.
    if (d0 > abs_sum[0]) {
      ++st.umbra_early_outs;
      st.d_min = std::min(st.d_min, d0 - abs_sum[0]);
      st.d_max = std::max(st.d_max, d0 + abs_sum[0]);
      return finish_uniform(i, ss, 0.0f);
    }
    // The S-triangles whose soft textured shadow volume holds p [Forest 2008 §5.1.3, §5.2.2]:
    // each increments the counter of its class for the samples behind one of its opaque texels.
    sc.pairs.clear();
    if (!stsv_bin.empty()) {
      const auto t0 = std::chrono::steady_clock::now();
      const Vec3 origin = ctx_.gbuffer.shadow_origin(i);
      const DVec3 p(origin);
      LightFrame f;
      bool framed = false;
      for (const uint32_t k : stsv_bin) {
        ++st.stsv.volume_tests;
        if (!stsv_.volumes[k].contains(p)) continue;
        if (!framed) f = light_frame(ctx_.light, origin), framed = true;
        StsvPair sp;
        sp.triangle = k;
        const stsv::STriangle& t = stsv_.triangles[k];
        if (!stsv::make_pair(t, p, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v),
                             pl ? &pl->projection() : nullptr, sp.pair))
          continue;
        ++st.stsv.pairs;
        ++sc.stsv_sum[t.layer_class];
        sc.pairs.push_back(sp);
      }
      st.stsv_ms += elapsed_ms(t0);
    }
    if (ncov == 0 && sc.pairs.empty()) {
      // Every sample has the centre's counts (lit, umbra, or uniformly attenuated).
      float t = d0 > 0 ? 0.0f : 1.0f;
      for (size_t j = 1; j < classes_.size() && t > 0.0f; ++j)
        t = pass_through(t, j, classes_[j].centre_counts[i]);
      for (size_t j = 0; j < classes_.size(); ++j) {
        st.d_min = std::min(st.d_min, classes_[j].centre_counts[i]);
        st.d_max = std::max(st.d_max, classes_[j].centre_counts[i]);
      }
      return finish_uniform(i, ss, t);
    }

    // Adaptive precision [§4.2.3]: 16-bit lanes unless this pixel's bound could overflow them.
    int64_t bound = 0;
    for (size_t j = 0; j < classes_.size(); ++j)
      bound =
          std::max<int64_t>(bound, std::abs(static_cast<int64_t>(classes_[j].centre_counts[i])) +
                                       abs_sum[j] + sc.stsv_sum[j]);
    if (bound < std::numeric_limits<int16_t>::max()) {
      return integrate(i, sc, sc.c16.data(), ss, st);
    }
    ++st.wide_counters;
    return integrate(i, sc, sc.c32.data(), ss, st);
  }

 private:
  bool emits(const Vec2& uv) const {
    if (!round_) return true;
    const Vec2 d = uv - Vec2(0.5f);
    return glm::dot(d, d) <= 0.25f;  // LightFrame::emits of a round light
  }

  /// The light left after `count` crossings of class j's surfaces [§4.3.3]: the exact product
  /// t^count, or the paper's counter-packing approximation, which subtracts (1 − t) per crossing
  /// (V_s = 1 − Sat(D + Σ (1 − t)·D_t)).
  float pass_through(float vis, size_t j, int32_t count) const {
    if (count <= 0 || vis == 0.0f) return vis;
    const double t = classes_[j].transmittance;
    if (options_.semi_opaque == DcsSemiOpaque::paper)
      return std::max(0.0f, vis - static_cast<float>((1.0 - t) * count));
    return vis * static_cast<float>(std::pow(t, count));
  }

  /// Algorithm 7 on the counters, then eq. 4.1 / 4.2 (and §4.3.3's transmittance).
  template <class Counter>
  float integrate(size_t i, Scratch& sc, Counter* counters, const dcs::SampleSet& ss,
                  RowStats& st) {
    const size_t classes = classes_.size();
    for (size_t j = 0; j < classes; ++j)
      std::fill(counters + j * n_, counters + (j + 1) * n_,
                static_cast<Counter>(classes_[j].centre_counts[i]));
    uint64_t updates = 0;
    for (const CoveredEdge& ce : sc.covered) {
      int first = 0, last = 0;
      ss.range(ce.region.v_lo, ce.region.v_hi, first, last);
      st.sample_tests += static_cast<uint64_t>(last - first);
      updates += dcs::apply_region(counters + ce.layer_class * n_ + first, ss.u.data() + first,
                                   ss.v.data() + first, last - first, ce.region, ce.delta);
    }
    st.covered_updates += updates;
    // §5.2.2: a covered opaque texel of an S-triangle increments D of that sample.
    const auto t0 = std::chrono::steady_clock::now();
    for (const StsvPair& sp : sc.pairs) {
      const stsv::STriangle& t = stsv_.triangles[sp.triangle];
      int first = 0, last = 0;
      ss.range(sp.pair.v_lo, sp.pair.v_hi, first, last);
      Counter* c = counters + t.layer_class * n_ + first;
      const int count = last - first;
      const int crossing = stsv::blocked_samples(sp.pair, t, ss.u.data() + first,
                                                 ss.v.data() + first, count, sc.flags.data());
      st.stsv.lookups += static_cast<uint64_t>(crossing);
      if (crossing == 0) continue;
      const uint8_t* blocked_s = sc.flags.data();
      uint64_t blocked = 0;
      for (int s = 0; s < count; ++s) {
        c[s] += blocked_s[s];
        blocked += blocked_s[s];
      }
      st.stsv.blocked += blocked;
    }
    if (!sc.pairs.empty()) st.stsv_ms += elapsed_ms(t0);
    Counter lo = counters[0], hi = counters[0];
    for (size_t s = 0; s < classes * n_; ++s) {
      lo = std::min(lo, counters[s]);
      hi = std::max(hi, counters[s]);
    }
    st.d_min = std::min<int32_t>(st.d_min, lo);
    st.d_max = std::max<int32_t>(st.d_max, hi);

    // Per-sample visibility: Sat(D) of the opaque class; the semi-opaque classes attenuate.
    float* vis = sc.vis.data();
    for (int s = 0; s < n_; ++s) vis[s] = counters[s] > 0 ? 0.0f : 1.0f;
    for (size_t j = 1; j < classes; ++j) {
      const Counter* cj = counters + j * n_;
      for (int s = 0; s < n_; ++s) vis[s] = pass_through(vis[s], j, cj[s]);
    }
    return finish(i, ss, vis);
  }

  float finish(size_t i, const dcs::SampleSet& ss, const float* vis) {
    const uint8_t* emit = ss.emit.data();
    if (out_.masks)
      for (int s = 0; s < n_; ++s)
        if (emit[s] && vis[s] == 0.0f) out_.masks->set_blocked(i, ss.index[s]);
    if (emission_) {
      const LightFrame frame = light_frame(ctx_.light, ctx_.gbuffer.shadow_origin(i));
      const SampleWeights w = accumulate_sample_weights(frame, emission_, ctx_.light.radiance,
                                                        ss.uv, std::span<const float>(vis, n_));
      (*out_.lit_rgb)[i] = w.visible_fraction_rgb();
      return w.visible_fraction();
    }
    float seen = 0.0f;
    int total = 0;
    for (int s = 0; s < n_; ++s) {
      seen += emit[s] ? vis[s] : 0.0f;
      total += emit[s];
    }
    return total > 0 ? std::min(1.0f, seen / static_cast<float>(total)) : 1.0f;
  }

  /// Every sample has visibility t.
  float finish_uniform(size_t i, const dcs::SampleSet& ss, float t) {
    if (out_.masks && t == 0.0f)
      for (int s = 0; s < n_; ++s)
        if (ss.emit[s]) out_.masks->set_blocked(i, ss.index[s]);
    if (emission_) (*out_.lit_rgb)[i] = Vec3(t);
    return t;
  }

  const ShadowContext& ctx_;
  const DcsOptions& options_;
  const std::vector<LayerClass>& classes_;
  const dcs::EdgeSet& edges_;
  const BinnedWedges* bw_;
  const stsv::StsvSet& stsv_;
  Visibility& out_;
  int n_;
  const Texture* emission_;
  bool round_;
  dcs::SampleSet shared_;  // the pixel-independent patterns, sorted once
};

/// Whether a straddling edge's weight is 0 for every point of the box [lo, hi]: each face plane
/// leaves the box on one side, and the sides cancel. On closed meshes most (box, straddling edge)
/// pairs: an edge whose face planes cut the light is a silhouette only from the thin region
/// between those planes.
bool zero_weight_over_box(const dcs::EdgeSet& edges, const dcs::Edge& e, const DVec3& lo,
                          const DVec3& hi) {
  if (e.face_count == 0) return false;
  const DVec3 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  int32_t m = 0;
  for (uint32_t f = e.face_begin; f < e.face_begin + e.face_count; ++f) {
    const dcs::EdgeFace& face = edges.faces[f];
    const double c = glm::dot(face.n, mid) - face.d,
                 r = glm::dot(glm::abs(face.n), half) * (1.0 + 1e-9) + 1e-12 * std::abs(face.d);
    if (!(std::abs(c) > r)) return false;  // the plane cuts the box: the weight varies
    m -= (c > 0.0 ? 1 : -1) * face.sign;
  }
  return m == 0;
}

/// Side of the pixel blocks whose shadow-origin boxes re-cull a tile's bin.
constexpr int kBlock = 4;

}  // namespace

Visibility dcs_visibility(const ShadowContext& ctx, const DcsOptions& options,
                          const wedge_pass::CasterMeshes* prepared) {
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  Visibility out;
  out.lit = Image<float>(g.width, g.height, 1.0f);
  if (light.is_textured()) out.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));
  if (ctx.want_masks) out.masks = SampleMasks(g.width, g.height, ctx.samples.count());

  double stsv_ms = 0.0;
  const dcs::Frame frame = dcs::prepare_frame(ctx, options, out, stsv_ms, prepared);
  const std::vector<LayerClass>& classes = frame.classes;
  const dcs::EdgeSet& edges = frame.edges;
  const BinnedWedges& bw = frame.bw;
  const stsv::StsvSet& sset = frame.stsv;
  const bool area = frame.area;
  const size_t alpha_triangles = frame.alpha_triangles;

  // Algorithm 7 per pixel, one tile row per task. Each tile's bin is culled again per 4×4 block
  // of pixels (its shadow origins' box against the wedge planes and the straddling weights), so
  // a pixel visits only the edges that can matter near it.
  auto start = std::chrono::steady_clock::now();
  Sampler sampler(ctx, options, classes, edges, area ? &bw : nullptr, sset, out);
  const int tiles_x = (g.width + kTile - 1) / kTile, tiles_y = (g.height + kTile - 1) / kTile;
  std::vector<RowStats> rows(tiles_y);
  const bool per_pixel_frame = frame_depends_on_receiver(light);
  const LightFrame fixed_frame = light_frame(light, light.center);
  parallel_rows(tiles_y, [&](int ty) {
    RowStats& st = rows[ty];
    std::vector<uint32_t> block;
    dcs::BlockWeights weights;
    const std::vector<uint32_t> none;
    for (int tx = 0; tx < tiles_x; ++tx) {
      const std::vector<uint32_t>& bin =
          area ? bw.bins[static_cast<size_t>(ty) * tiles_x + tx] : none;
      const std::vector<uint32_t>& stsv_bin = sset.bin_of_tile(tx, ty);
      for (int by = ty * kTile; by < std::min(g.height, (ty + 1) * kTile); by += kBlock) {
        for (int bx = tx * kTile; bx < std::min(g.width, (tx + 1) * kTile); bx += kBlock) {
          const int y1 = std::min(g.height, by + kBlock), x1 = std::min(g.width, bx + kBlock);
          DVec3 lo(kInfinity), hi(-kInfinity);
          for (int y = by; y < y1; ++y)
            for (int x = bx; x < x1; ++x) {
              const size_t i = static_cast<size_t>(y) * g.width + x;
              if (ctx.receivers[i] != kActive) continue;
              lo = glm::min(lo, DVec3(g.shadow_origin(i)));
              hi = glm::max(hi, DVec3(g.shadow_origin(i)));
            }
          if (!(lo.x <= hi.x)) continue;  // no active pixel
          block.clear();
          for (const uint32_t k : bin)
            if (!zero_weight_over_box(edges, edges.edges[bw.group[k]], lo, hi) &&
                bw.wedges[k].may_hold_box(lo, hi))
              block.push_back(k);
          st.block_entries += block.size();
          weights.assign(edges, block, bw.group);
          for (int y = by; y < y1; ++y)
            for (int x = bx; x < x1; ++x) {
              const size_t i = static_cast<size_t>(y) * g.width + x;
              if (ctx.receivers[i] != kActive) continue;
              if (block.empty() && stsv_bin.empty()) {
                out.lit[i] = sampler.shade(i, nullptr, block, nullptr, stsv_bin, st);
                continue;
              }
              const PixelLight pl(light, fixed_frame, per_pixel_frame, g.shadow_origin(i));
              if (!pl.valid()) ++st.pass.fallbacks;  // in the light's plane: the centre count
              out.lit[i] =
                  sampler.shade(i, pl.valid() ? &pl : nullptr, block, &weights, stsv_bin, st);
            }
        }
      }
    }
  });
  out.times.add("sampling", elapsed_ms(start));

  RowStats total;
  for (const RowStats& r : rows) {
    total.edge_pixel_pairs += r.edge_pixel_pairs;
    total.covered_updates += r.covered_updates;
    total.sample_tests += r.sample_tests;
    total.straddle_weights += r.straddle_weights;
    total.penumbra_pixels += r.penumbra_pixels;
    total.umbra_early_outs += r.umbra_early_outs;
    total.wide_counters += r.wide_counters;
    total.max_edges = std::max(total.max_edges, r.max_edges);
    total.d_min = std::min(total.d_min, r.d_min);
    total.d_max = std::max(total.d_max, r.d_max);
    total.pass += r.pass;
    total.block_entries += r.block_entries;
    total.stsv += r.stsv;
    total.stsv_ms += r.stsv_ms;
  }
  size_t active = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) active += ctx.receivers[i] == kActive;
  const double per_active = 1.0 / static_cast<double>(std::max<size_t>(1, active));
  const double per_penumbra =
      1.0 / static_cast<double>(std::max<uint64_t>(1, total.penumbra_pixels));
  Counters& k = out.counters;
  k["silhouette_edges"] = static_cast<double>(edges.edges.size());
  k["straddling_edges"] = static_cast<double>(edges.straddling);
  k["wedges"] = static_cast<double>(bw.wedges.size());
  k["wedge_construction_fallbacks"] = static_cast<double>(bw.degenerate);
  k["layer_classes"] = static_cast<double>(classes.size());
  k["alpha_textured_as_opaque"] = static_cast<double>(alpha_triangles);
  k["light_plane_fallbacks"] = static_cast<double>(total.pass.fallbacks);
  size_t binned = 0;
  for (const auto& bin : bw.bins) binned += bin.size();
  k["tile_bin_entries"] = static_cast<double>(binned);
  k["block_bin_entries"] = static_cast<double>(total.block_entries);
  k["pixel_tests"] = static_cast<double>(total.pass.tests);
  k["pixels_inside_wedges"] = static_cast<double>(total.pass.inside);
  k["penumbra_pixels"] = static_cast<double>(total.penumbra_pixels);
  k["edges_per_penumbra_pixel"] = static_cast<double>(total.edge_pixel_pairs) * per_penumbra;
  k["edges_per_pixel_max"] = static_cast<double>(total.max_edges);
  k["straddling_weights"] = static_cast<double>(total.straddle_weights);
  k["covered_sample_updates"] = static_cast<double>(total.covered_updates);
  k["covered_updates_per_pixel"] = static_cast<double>(total.covered_updates) * per_active;
  k["sample_tests"] = static_cast<double>(total.sample_tests);
  k["umbra_early_outs"] = static_cast<double>(total.umbra_early_outs);
  k["int32_counter_pixels"] = static_cast<double>(total.wide_counters);
  k["counter_min"] = total.d_min <= total.d_max ? total.d_min : 0.0;
  k["counter_max"] = total.d_min <= total.d_max ? total.d_max : 0.0;
  // The STSV stage: volumes and bins; their per-sample work is part of `sampling`.
  if (options.alpha_stsv) {
    stsv::report(stsv::summarize(sset, total.stsv, stsv_ms), out);
    // The S-triangles' share of `sampling` (thread time, summed over the worker threads).
    k["stsv_sampling_thread_ms"] = total.stsv_ms;
  }
  return out;
}

namespace {

class Dcs final : public ShadowMethod {
 public:
  explicit Dcs(DcsOptions options) : options_(options) {}
  /// The casters' adjacency (edges, re-oriented and de-duplicated meshes) is scene-static.
  void prepare(const Scene& scene) override {
    const auto start = std::chrono::steady_clock::now();
    casters_ = std::make_unique<const CasterMeshes>(caster_meshes(scene));
    unreported_prepare_ms_ = elapsed_ms(start);
  }
  Visibility compute(const ShadowContext& ctx) override {
    Visibility v = dcs_visibility(ctx, options_, casters_.get());
    // The adjacency's time, once, in the stage that built it when it was built per light.
    v.times.add("setup", std::exchange(unreported_prepare_ms_, 0.0));
    return v;
  }

 private:
  DcsOptions options_;
  std::unique_ptr<const CasterMeshes> casters_;
  double unreported_prepare_ms_ = 0.0;
};

}  // namespace

void register_dcs(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "dcs";
  info.summary =
      "depth complexity sampling: per light sample, the shadow-volume count from the light centre "
      "plus the steps of every penumbra wedge's projected edge; the same per-sample answer as "
      "raytrace without a ray; perforated (alpha-textured) triangles through soft textured shadow "
      "volumes (alpha=stsv)";
  info.reference = "[Forest 2008 ch. 4, Algorithms 7-9, §5.2.2; Laine 2005]";
  info.sample_exact = true;
  info.options = {
      {"silhouettes",
       OptionType::choice,
       "light",
       "silhouette edges w.r.t. the whole light with per-receiver weights (light, exact; Forest "
       "4.1.4) or from the light centre only (centre: the standard detection, under-estimated "
       "penumbrae of fig. 4.3a)",
       {"light", "centre"}},
      wedge_construction_option(),
      stsv::alpha_option(),
      {"semi_opaque",
       OptionType::choice,
       "exact",
       "semi-opaque occluders (Forest 4.3.3): exact product of the transmittances per sample, or "
       "paper (the counter-packing approximation 1 - Sat(D + sum (1 - t) D_t), exact for one "
       "layer)",
       {"exact", "paper"}},
  };
  info.create = [](const MethodOptions& o) {
    DcsOptions d;
    d.silhouettes = o.get_choice("silhouettes") == "centre" ? dcs::SilhouetteMode::centre
                                                            : dcs::SilhouetteMode::light;
    d.construction = wedge_construction_of(o);
    d.semi_opaque =
        o.get_choice("semi_opaque") == "paper" ? DcsSemiOpaque::paper : DcsSemiOpaque::exact;
    d.alpha_stsv = stsv::uses_stsv(o);
    return std::make_unique<Dcs>(d);
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
