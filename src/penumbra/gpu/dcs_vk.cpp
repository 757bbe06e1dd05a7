// `dcs` on Vulkan: depth complexity sampling [Forest 2008 ch. 4] with the per-receiver work in
// compute shaders, on the frame's G-buffer and light samples:
//   host:  the CPU method's own setup (wedges/dcs_frame.hpp: layer classes, silhouette edges
//          w.r.t. the whole light and their face planes, centre counts, wedges and S-triangle
//          volumes binned to 16×16 tiles) and each pixel's light frame and projection
//          (wedges/pass.hpp PixelLight);
//   GPU:   counters := centre counts (dcs_init), per pixel the wedges of its tile's bin — weight,
//          wedge test, clipped projected edge, covered region, signed counter steps (dcs_edges,
//          in chunks of the bins) — and the S-triangles of its tile's bin — volume test, J, the
//          opaque texels the samples' segments cross (dcs_stsv) — then the CPU's three outcomes
//          per pixel and V (dcs_finish);
//   host:  masks and V read back; a textured light's weighting from the per-sample visibility.
// Each step is the CPU's arithmetic (double where the CPU uses double, `precise`), so the masks
// are the CPU dcs's, hence `raytrace`'s.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/wedge_data.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/material.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/wedges/dcs_counters.hpp"
#include "penumbra/shadows/wedges/dcs_frame.hpp"
#include "penumbra/shadows/wedges/stsv_lookup.hpp"
#include "penumbra/shadows/wedges/wedges.hpp"

namespace penumbra::gpu {

namespace {

using dcs::Frame;

// shaders/dcs.glsl layouts (scalar).
struct EdgeGpu {
  int32_t centre_multiplicity;
  uint32_t face_begin, face_count, layer_class;
};
struct FaceGpu {
  double n[3];
  double d;
  int32_t sign, pad;
};
static_assert(sizeof(FaceGpu) == 40);
struct PixelGpu {
  double p[3], to_u[3], to_v[3], to_w[3];
  double corner[3], edge_u[3], edge_v[3];
  uint32_t tile, flags;
};
static_assert(sizeof(PixelGpu) == 176);
struct STriGpu {
  double v0[3], e1[3], e2[3];
  double to_triangle[3][3];  // rows
  float uv[3][2];
  uint32_t texel_offset;
  int32_t width, height;
  uint32_t layer_class;
  int32_t side_count, pad;
};
static_assert(sizeof(STriGpu) == 192);
constexpr uint32_t kValid = 1, kRound = 2, kTauNeg = 4;

struct InitPush {
  VkDeviceAddress centre, counters;
  uint32_t na, n, total;
};
// sample_stride, band_stride: 0 for a pattern shared by every pixel, n and k + 1 for per-pixel
// patterns (each active pixel's own sorted samples and bands, in pixel order).
struct EdgesPush {
  VkDeviceAddress pix, wedges, edges, faces, bin_begin, bin_entries, samples, band_begin, counters,
      state;
  uint32_t na, n, k, first, chunk, sample_stride, band_stride;
};
struct StsvPush {
  VkDeviceAddress pix, tris, sides, bin_begin, bin_entries, texels, samples, band_begin, counters,
      state;
  uint32_t na, n, k, first, chunk;
  float min_inverse_t;
  uint32_t sample_stride, band_stride;
};
struct FinishPush {
  VkDeviceAddress centre, state, counters, attenuation, emit_index, lit, masks, sample_vis;
  uint32_t na, n, classes, table, paper, words, want_vis, sample_stride;
};
static_assert(sizeof(EdgesPush) <= kPushBytes && sizeof(StsvPush) <= kPushBytes &&
              sizeof(FinishPush) <= kPushBytes);

/// Bin entries one dispatch of dcs_edges walks per pixel. llvmpipe stops any invocation after
/// 65535 loop iterations in all (its guard against endless loops): an entry costs up to ~20 (faces
/// and planes) plus one per sample of its band range. Other devices walk the whole bin at once.
uint32_t bin_chunk(const VulkanContext& vk, int samples) {
  if (vk.info().type != "cpu") return UINT32_MAX / 2;
  return std::max<uint32_t>(1, 60000u / static_cast<uint32_t>(samples + 32));
}

/// The S-triangles, their volume sides (two per triangle) and the alpha textures as bits
/// (alpha ≥ kAlphaCutoff: the texel blocks).
struct StsvData {
  std::vector<STriGpu> tris;
  std::vector<WedgeGpu> sides;
  std::vector<uint32_t> texels;
};
StsvData stsv_data(const stsv::StsvSet& set) {
  StsvData out;
  std::map<const Texture*, uint32_t> offset_of;
  for (size_t t = 0; t < set.triangles.size(); ++t) {
    const stsv::STriangle& src = set.triangles[t];
    STriGpu dst{};
    put3(dst.v0, src.v0), put3(dst.e1, src.e1), put3(dst.e2, src.e2);
    for (int r = 0; r < 3; ++r)  // glm is column-major: row r is (m[0][r], m[1][r], m[2][r])
      put3(dst.to_triangle[r],
           DVec3(src.to_triangle[0][r], src.to_triangle[1][r], src.to_triangle[2][r]));
    for (int c = 0; c < 3; ++c) dst.uv[c][0] = src.uv[c].x, dst.uv[c][1] = src.uv[c].y;
    const Texture& alpha = *src.alpha;
    auto [it, added] = offset_of.emplace(&alpha, static_cast<uint32_t>(out.texels.size()));
    if (added)
      for (int y = 0; y < alpha.height; ++y)
        for (int x = 0; x < alpha.width; ++x)
          out.texels.push_back(alpha.channel(x, y, 0) >= kAlphaCutoff ? 1u : 0u);
    dst.texel_offset = it->second;
    dst.width = alpha.width, dst.height = alpha.height;
    dst.layer_class = src.layer_class;
    const stsv::Volume& v = set.volumes[t];
    dst.side_count = v.side_count;
    out.tris.push_back(dst);
    for (int k = 0; k < 2; ++k) out.sides.push_back(to_gpu(v.sides[k], 0));
  }
  return out;
}

/// The light samples sorted into bands of v, as the CPU's Sampler sorts them, as the shaders read
/// them: (u, v) pairs (also the host's, for a textured light's weighting), emits | LightSamples
/// index, the band starts — one set shared by every pixel, or one per active pixel (per-pixel
/// patterns), appended in pixel order.
struct Samples {
  bool per_pixel = false;
  std::vector<Vec2> uv;  // two tightly packed floats each: the shaders' vec2 array
  std::vector<uint32_t> emit_index;
  std::vector<int32_t> band_begin;

  void append(const dcs::SampleSet& set) {
    uv.insert(uv.end(), set.uv.begin(), set.uv.end());
    for (size_t s = 0; s < set.uv.size(); ++s)
      emit_index.push_back((set.emit[s] ? 0x10000u : 0u) | set.index[s]);
    band_begin.insert(band_begin.end(), set.band_begin.begin(), set.band_begin.end());
  }
  /// The sorted positions of active pixel a's samples.
  std::span<const Vec2> of_pixel(size_t a, int n) const {
    return {uv.data() + (per_pixel ? a * n : 0), static_cast<size_t>(n)};
  }
};
static_assert(sizeof(Vec2) == 2 * sizeof(float));
Samples samples_of(const ShadowContext& ctx, const std::vector<uint32_t>& active) {
  Samples out;
  const bool round = ctx.light.shape == LightShape::disk || ctx.light.shape == LightShape::sphere;
  auto emits = [&](const Vec2& uv) {
    if (!round) return true;
    const Vec2 d = uv - Vec2(0.5f);
    return glm::dot(d, d) <= 0.25f;  // LightFrame::emits of a round light
  };
  dcs::SampleSet set;
  if (!ctx.samples.per_pixel()) {
    set.assign(ctx.samples.shared_samples(), ctx.samples.k(), emits);
    out.append(set);
    return out;
  }
  // Per-pixel patterns (decorrelated, interleaved): each pixel's samples, sorted as the CPU's
  // Sampler::shade sorts them for that pixel.
  const uint64_t bytes = uint64_t{active.size()} * ctx.samples.count() * 12;
  if (bytes >= (uint64_t{1} << 31))
    throw Error("dcs on vulkan: per-pixel sample patterns need " + std::to_string(bytes >> 20) +
                " MiB of samples at this size (at most 2 GiB); lower the resolution or the "
                "sample count");
  out.per_pixel = true;
  std::vector<Vec2> uv(ctx.samples.count());
  const int width = ctx.gbuffer.width;
  for (const uint32_t i : active) {
    ctx.samples.pixel_samples(static_cast<int>(i % width), static_cast<int>(i / width), uv);
    set.assign(uv, ctx.samples.k(), emits);
    out.append(set);
  }
  return out;
}

/// Per active pixel: shadow origin, tile, light frame and projection (PixelLight, as the CPU's
/// pass computes them).
std::vector<PixelGpu> pixels_of(const ShadowContext& ctx, const Frame& fr,
                                const std::vector<uint32_t>& active) {
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  const bool any_bins = fr.area || !fr.stsv.empty();
  const bool per_pixel_frame = frame_depends_on_receiver(light);
  const LightFrame fixed_frame = light_frame(light, light.center);
  std::vector<PixelGpu> pixels(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    const uint32_t i = active[a];
    const int x = static_cast<int>(i % g.width), y = static_cast<int>(i / g.width);
    PixelGpu& px = pixels[a];
    px = {};
    put3(px.p, DVec3(g.shadow_origin(i)));
    if (!any_bins) continue;
    px.tile =
        static_cast<uint32_t>((y / wedge_pass::kTile) * fr.setup.tiles_x + x / wedge_pass::kTile);
    const LightFrame f = light_frame(light, g.shadow_origin(i));
    put3(px.corner, DVec3(f.corner)), put3(px.edge_u, DVec3(f.edge_u));
    put3(px.edge_v, DVec3(f.edge_v));
    const wedge_pass::PixelLight pl(light, fixed_frame, per_pixel_frame, g.shadow_origin(i));
    if (!pl.valid()) continue;
    const LightProjection& lp = pl.projection();
    put3(px.to_u, lp.to_u), put3(px.to_v, lp.to_v), put3(px.to_w, lp.to_w);
    px.flags = kValid | (pl.round() ? kRound : 0) | (pl.tau() < 0.0 ? kTauNeg : 0);
  }
  return pixels;
}

/// The wedges, their edges and the straddling edges' face planes.
struct Geometry {
  std::vector<WedgeGpu> wedges;
  std::vector<EdgeGpu> edges;
  std::vector<FaceGpu> faces;
};
Geometry geometry_of(const Frame& fr) {
  Geometry out;
  for (size_t w = 0; w < fr.bw.wedges.size(); ++w)
    out.wedges.push_back(to_gpu(fr.bw.wedges[w], fr.bw.group[w]));
  for (const dcs::Edge& e : fr.edges.edges)
    out.edges.push_back({e.centre_multiplicity, e.face_begin, e.face_count, e.layer_class});
  for (const dcs::EdgeFace& f : fr.edges.faces) {
    FaceGpu fg{};
    put3(fg.n, f.n);
    fg.d = f.d;
    fg.sign = f.sign;
    out.faces.push_back(fg);
  }
  return out;
}

/// Centre counts per class (class·na + pixel), and the attenuation of the semi-opaque classes per
/// crossing count — the CPU's float(pow(t, count)) or float((1 − t)·count) — tabulated up to the
/// largest count a pixel can reach: its centre count plus every edge of the class stepping once
/// by its largest weight plus every S-triangle of the class once.
struct Classes {
  uint32_t count = 0;
  std::vector<int32_t> centre;
  uint32_t table = 1;
  std::vector<float> attenuation;  // class·table + crossings
};
Classes classes_of(const Frame& fr, const std::vector<uint32_t>& active, DcsSemiOpaque mode) {
  Classes out;
  out.count = static_cast<uint32_t>(fr.classes.size());
  const size_t na = active.size();
  out.centre.resize(out.count * na);
  std::vector<int64_t> reach(out.count, 0);
  for (uint32_t j = 0; j < out.count; ++j)
    for (size_t a = 0; a < na; ++a) {
      const int32_t c = fr.classes[j].centre_counts[active[a]];
      out.centre[j * na + a] = c;
      reach[j] = std::max<int64_t>(reach[j], std::abs(c));
    }
  for (const dcs::Edge& e : fr.edges.edges)
    reach[e.layer_class] += std::max<int64_t>(e.centre_multiplicity, e.face_count);
  for (const stsv::STriangle& t : fr.stsv.triangles) ++reach[t.layer_class];
  int64_t table = 1;
  for (uint32_t j = 1; j < out.count; ++j) table = std::max(table, reach[j] + 1);
  if (table > (int64_t{1} << 24))
    throw Error("dcs on vulkan: semi-opaque depth complexity too large to tabulate");
  out.table = static_cast<uint32_t>(table);
  out.attenuation.assign(size_t{out.count} * out.table, 0.0f);
  for (uint32_t j = 1; j < out.count; ++j)
    for (uint32_t c = 0; c < out.table; ++c) {
      const double t = fr.classes[j].transmittance;
      out.attenuation[size_t{j} * out.table + c] =
          mode == DcsSemiOpaque::paper ? static_cast<float>((1.0 - t) * static_cast<double>(c))
                                       : static_cast<float>(std::pow(t, static_cast<int>(c)));
    }
  return out;
}

/// Everything the shaders read, on the device, and what they write.
struct DeviceData {
  Buffer pixels, wedges, edges, faces, bin_begin, bin_entries, stsv_begin, stsv_entries, stsv_tris,
      stsv_sides, texels, samples, band_begin, centre, attenuation, emit_index;
  Buffer counters, state, lit, masks, sample_vis;
};

class DcsVk final : public ShadowMethod {
 public:
  DcsVk(Backend& backend, const MethodOptions& o) : backend_(backend) {
    options_.silhouettes = o.get_choice("silhouettes") == "centre" ? dcs::SilhouetteMode::centre
                                                                   : dcs::SilhouetteMode::light;
    options_.construction = wedge_construction_of(o);
    options_.semi_opaque =
        o.get_choice("semi_opaque") == "paper" ? DcsSemiOpaque::paper : DcsSemiOpaque::exact;
    options_.alpha_stsv = stsv::uses_stsv(o);
  }

  /// The casters' adjacency is scene-static, as for the CPU dcs.
  void prepare(const Scene& scene) override {
    const auto start = std::chrono::steady_clock::now();
    casters_ = std::make_unique<const wedge_pass::CasterMeshes>(wedge_pass::caster_meshes(scene));
    unreported_prepare_ms_ = elapsed_ms(start);
  }

  Visibility compute(const ShadowContext& ctx) override {
    VulkanContext& vk = backend_.context();
    if (!vk.has_float64())
      throw Error("dcs on vulkan needs shaderFloat64, which " + vk.device_name() + " lacks");
    const GBuffer& g = ctx.gbuffer;
    const int n = ctx.samples.count();
    Visibility out;
    out.lit = Image<float>(g.width, g.height, 1.0f);
    if (ctx.light.is_textured()) out.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));
    if (ctx.want_masks) out.masks = SampleMasks(g.width, g.height, n);

    double stsv_ms = 0.0;
    const Frame fr = dcs::prepare_frame(ctx, options_, out, stsv_ms, casters_.get());
    out.times.add("setup", std::exchange(unreported_prepare_ms_, 0.0));
    auto t0 = std::chrono::steady_clock::now();
    std::vector<uint32_t> active;
    for (size_t i = 0; i < g.pixel_count(); ++i)
      if (ctx.receivers[i] == kActive) active.push_back(static_cast<uint32_t>(i));
    const uint32_t na = static_cast<uint32_t>(active.size());
    const Samples samples = samples_of(ctx, active);
    const Classes classes = classes_of(fr, active, options_.semi_opaque);
    const uint64_t counter_count = uint64_t{classes.count} * n * na;
    if (counter_count >= (uint64_t{1} << 31))
      throw Error("dcs on vulkan: " + std::to_string(counter_count) +
                  " counters (pixels × samples × layer classes) exceed 2^31; lower the "
                  "resolution or the sample count");
    const Bins bins(fr.bw.bins);
    const Bins stsv_bins(fr.stsv.empty() ? std::vector<std::vector<uint32_t>>{} : fr.stsv.bins);
    const std::vector<PixelGpu> pixels = pixels_of(ctx, fr, active);
    const Geometry geometry = geometry_of(fr);
    const StsvData stsv = stsv_data(fr.stsv);
    out.times.add("gpu_setup_host", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    const uint32_t words = static_cast<uint32_t>((n + 31) / 32);
    const bool want_vis = ctx.light.is_textured();
    const DeviceData d{
        vk.upload(pixels),
        vk.upload(geometry.wedges),
        vk.upload(geometry.edges),
        vk.upload(geometry.faces),
        vk.upload(bins.begin),
        vk.upload(bins.entries),
        vk.upload(stsv_bins.begin),
        vk.upload(stsv_bins.entries),
        vk.upload(stsv.tris),
        vk.upload(stsv.sides),
        vk.upload(stsv.texels),
        vk.upload(samples.uv),
        vk.upload(samples.band_begin),
        vk.upload(classes.centre),
        vk.upload(classes.attenuation),
        vk.upload(samples.emit_index),
        Buffer(vk, std::max<uint64_t>(counter_count, 1) * 4, Memory::device),
        Buffer(vk, std::max<size_t>(na, 1) * 8, Memory::device),
        Buffer(vk, std::max<size_t>(na, 1) * 4, Memory::device),
        Buffer(vk, std::max<size_t>(size_t{na} * words, 1) * 4, Memory::device),
        Buffer(vk, want_vis ? std::max<size_t>(size_t{na} * n, 1) * 4 : 16, Memory::device)};
    out.times.add("wall_upload", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    if (na > 0) {
      CommandList cl(vk);
      const uint32_t un = static_cast<uint32_t>(n), k = static_cast<uint32_t>(ctx.samples.k());
      const uint32_t sample_stride = samples.per_pixel ? un : 0u;
      const uint32_t band_stride = samples.per_pixel ? k + 1u : 0u;
      cl.fill(d.state, 0);
      cl.fill(d.masks, 0);
      cl.dispatch(programs().get(Shader::dcs_init),
                  InitPush{d.centre.address(), d.counters.address(), na, un,
                           static_cast<uint32_t>(counter_count)},
                  counter_count);
      cl.barrier();
      cl.mark("init");
      const uint32_t chunk = bin_chunk(vk, n);
      for (uint32_t first = 0; first < bins.longest; first += chunk) {
        cl.dispatch(
            programs().get(Shader::dcs_edges),
            EdgesPush{d.pixels.address(), d.wedges.address(), d.edges.address(), d.faces.address(),
                      d.bin_begin.address(), d.bin_entries.address(), d.samples.address(),
                      d.band_begin.address(), d.counters.address(), d.state.address(), na, un, k,
                      first, chunk, sample_stride, band_stride},
            na);
        cl.barrier();
      }
      cl.mark("edges");
      for (uint32_t first = 0; first < stsv_bins.longest; first += chunk) {
        cl.dispatch(programs().get(Shader::dcs_stsv),
                    StsvPush{d.pixels.address(), d.stsv_tris.address(), d.stsv_sides.address(),
                             d.stsv_begin.address(), d.stsv_entries.address(), d.texels.address(),
                             d.samples.address(), d.band_begin.address(), d.counters.address(),
                             d.state.address(), na, un, k, first, chunk, stsv::kMinInverseT,
                             sample_stride, band_stride},
                    na);
        cl.barrier();
      }
      if (stsv_bins.longest > 0) cl.mark("stsv");
      cl.dispatch(programs().get(Shader::dcs_finish),
                  FinishPush{d.centre.address(), d.state.address(), d.counters.address(),
                             d.attenuation.address(), d.emit_index.address(), d.lit.address(),
                             d.masks.address(), d.sample_vis.address(), na, un, classes.count,
                             classes.table, options_.semi_opaque == DcsSemiOpaque::paper ? 1u : 0u,
                             words, want_vis ? 1u : 0u, sample_stride},
                  na);
      cl.barrier();
      cl.mark("finish");
      cl.submit(&out.times);
    }
    out.times.add("wall_gpu", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    read_back(ctx, d, active, samples, out);
    out.times.add("wall_readback", elapsed_ms(t0));

    Counters& c = out.counters;
    c["silhouette_edges"] = static_cast<double>(fr.edges.edges.size());
    c["straddling_edges"] = static_cast<double>(fr.edges.straddling);
    c["wedges"] = static_cast<double>(fr.bw.wedges.size());
    c["tile_bin_entries"] = static_cast<double>(bins.entries.size());
    c["stsv_triangles"] = static_cast<double>(fr.stsv.triangles.size());
    c["layer_classes"] = static_cast<double>(classes.count);
    c["alpha_textured_as_opaque"] = static_cast<double>(fr.alpha_triangles);
    c["active_pixels"] = static_cast<double>(na);
    return out;
  }

 private:
  Programs& programs() { return backend_.programs(); }

  /// V and the masks into `out`; a textured light's RGB weighting (eq. 4.2) from the per-sample
  /// visibility, as the CPU's Sampler::finish does, for the pixels that were not uniform.
  void read_back(const ShadowContext& ctx, const DeviceData& d, const std::vector<uint32_t>& active,
                 const Samples& samples, Visibility& out) {
    VulkanContext& vk = backend_.context();
    const size_t na = active.size();
    const int n = ctx.samples.count();
    const uint32_t words = static_cast<uint32_t>((n + 31) / 32);
    const std::vector<float> lit = vk.download<float>(d.lit, na);
    const std::vector<uint32_t> mask_words = vk.download<uint32_t>(d.masks, na * words);
    const Texture* emission = ctx.light.is_textured()
                                  ? &wedge_pass::emission_texture(ctx.scene, ctx.light, "dcs")
                                  : nullptr;
    std::vector<int32_t> state;
    std::vector<float> vis;
    if (emission) {
      state = vk.download<int32_t>(d.state, na * 2);
      vis = vk.download<float>(d.sample_vis, na * n);
    }
    for (size_t a = 0; a < na; ++a) {
      const uint32_t i = active[a];
      out.lit[i] = lit[a];
      if (out.masks) {
        uint64_t* m = out.masks->pixel(i);
        for (uint32_t w = 0; w < words; ++w)
          m[w >> 1] |= uint64_t{mask_words[a * words + w]} << (32 * (w & 1));
      }
      if (!emission) continue;
      if (state[2 * a] != 2) {  // uniform: every sample has the same visibility
        (*out.lit_rgb)[i] = Vec3(lit[a]);
        continue;
      }
      const LightFrame frame = light_frame(ctx.light, ctx.gbuffer.shadow_origin(i));
      const SampleWeights w =
          accumulate_sample_weights(frame, emission, ctx.light.radiance, samples.of_pixel(a, n),
                                    std::span<const float>(vis.data() + a * n, n));
      (*out.lit_rgb)[i] = w.visible_fraction_rgb();
      out.lit[i] = w.visible_fraction();
    }
  }

  Backend& backend_;
  DcsOptions options_;
  std::unique_ptr<const wedge_pass::CasterMeshes> casters_;
  double unreported_prepare_ms_ = 0.0;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_dcs_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<DcsVk>(backend, options);
}

}  // namespace penumbra::gpu
