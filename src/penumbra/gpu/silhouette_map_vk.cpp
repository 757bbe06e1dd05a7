// `silhouette_map` on Vulkan [Valient 2005 §2]: the depth map by the Vulkan depth pass
// (gpu/depth_pass.hpp, exact vs the CPU), its nearest depth by depth_min.comp (soft mode's band);
// on the host the TAM (build_tam, once per scene in prepare()), the silhouette test (eq. 1), the
// §2.1.1 correction and the eq. 2 scaling per face — linear in the faces — and the binning of the
// scaled covers to 16×16 tiles; on the GPU the silhouette pass (silmap_layer.comp: per texel the
// faces of its tile in face order, so the LESSEQUAL merge sees the CPU's order) and the final
// lookup of eq. 4 (silmap_lookup.comp). Both shaders compute in double as the CPU does.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <span>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/depth_pass.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/depth_maps/shadow_map.hpp"
#include "penumbra/shadows/depth_maps/silhouette_map.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::gpu {

namespace {

constexpr int kTile = 16;  // silmap_layer.comp's tiles (one workgroup each)

// silmap_layer.comp's Face (scalar layout).
struct FaceGpu {
  double sx[3], sy[3], sz[3], side[3];
  double ux[3], uy[3], len[3];
  double bx[3], by[3], ex[3], ey[3], sgn[3];
  int32_t x_lo, x_hi, y_lo, y_hi;
  uint32_t mask, owns, orient, pad;
};
static_assert(sizeof(FaceGpu) == 320);

struct LayerPush {
  VkDeviceAddress faces, tiles, bin_begin, bin_faces, distance, depth, visited;
  double half_band, span_radius;
  uint32_t res, tiles_x, tile_count, first, chunk;
};
static_assert(sizeof(LayerPush) <= kPushBytes);

// silmap_lookup.comp's Params (scalar layout).
struct LookupParams {
  double eye[3], right[3], up[3], forward[3];
  double tan_half_x, tan_half_y, texel_tan, resolution, bias, slope_bias;
  double half_band, radius, row_width_max;
  double cos_k[4], sin_k[4];
  int32_t rows;
};

struct LookupPush {
  VkDeviceAddress params, points, map, distance, depth, table, vis;
  uint32_t n;
};
static_assert(sizeof(LookupPush) <= kPushBytes);

struct MinPush {
  VkDeviceAddress depth, result;
  uint32_t n;
};
constexpr uint32_t kMinTexelsPerThread = 64;  // depth_min.comp's kTexelsPerThread

/// Bin entries per dispatch: llvmpipe stops an invocation after 65535 loop iterations.
uint32_t entry_chunk(const VulkanContext& vk) {
  return vk.info().type == "cpu" ? 60000u : UINT32_MAX / 2;
}

int clamp_int(double v, int res) {
  return static_cast<int>(std::clamp(v, -2.0, static_cast<double>(res) + 2.0));
}

/// The GPU form of one face: rasterize_triangle_spans' setup of the scaled cover (orientation,
/// edge bases, top-left ownership, texel box) and silhouette_spans' per-edge directions, computed
/// here with the CPU's expressions. False when no texel can take the face (zero area, or no texel
/// both in the cover and near a silhouette edge).
bool to_gpu(const silmap::SilFace& f, int res, double span_radius, FaceGpu& g) {
  const DVec3 &a0 = f.scaled[0], &b0 = f.scaled[1], &c0 = f.scaled[2];
  const double area = (b0.x - a0.x) * (c0.y - a0.y) - (b0.y - a0.y) * (c0.x - a0.x);
  if (!(area != 0.0) || !std::isfinite(area)) return false;
  g = FaceGpu{};
  const bool cw = area > 0.0;
  const DVec3* v[3] = {&a0, cw ? &b0 : &c0, cw ? &c0 : &b0};
  for (int i = 0; i < 3; ++i) {
    const DVec3& p = *v[(i + 1) % 3];
    const DVec3& q = *v[(i + 2) % 3];
    const bool p_first = p.x < q.x || (p.x == q.x && p.y < q.y);
    const DVec3& base = p_first ? p : q;
    const DVec3& other = p_first ? q : p;
    g.bx[i] = base.x, g.by[i] = base.y;
    g.ex[i] = other.x - base.x, g.ey[i] = other.y - base.y;
    g.sgn[i] = p_first ? 1.0 : -1.0;
    const double dx = q.x - p.x, dy = q.y - p.y;  // raster_detail::owns_centres
    if (dy < 0.0 || (dy == 0.0 && dx > 0.0)) g.owns |= 1u << i;
  }
  g.y_lo = std::max(0, clamp_int(std::floor(std::min({a0.y, b0.y, c0.y}) - 0.5), res));
  g.y_hi = std::min(res - 1, clamp_int(std::ceil(std::max({a0.y, b0.y, c0.y}) - 0.5), res));
  g.x_lo = std::max(0, clamp_int(std::floor(std::min({a0.x, b0.x, c0.x}) - 0.5), res));
  g.x_hi = std::min(res - 1, clamp_int(std::ceil(std::max({a0.x, b0.x, c0.x}) - 0.5), res));
  if (g.y_lo > g.y_hi || g.x_lo > g.x_hi) return false;
  for (int c = 0; c < 3; ++c) {
    const DVec3 &a = f.s[c], &b = f.s[(c + 1) % 3];
    g.sx[c] = a.x, g.sy[c] = a.y, g.sz[c] = a.z, g.side[c] = f.side[c];
    const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
    g.len[c] = len;
    if (len >= 1e-12) g.ux[c] = ex / len, g.uy[c] = ey / len;
  }
  g.mask = static_cast<uint32_t>(f.mask);
  // Every texel in a span has its centre within radius·√2 of its edge's endpoints' box: the box
  // the shader tests first, and the binning's, is the cover's cut to that.
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int c = 0; c < 3; ++c) {
    if (!(f.mask & (1 << c))) continue;
    for (const DVec3* p : {&f.s[c], &f.s[(c + 1) % 3]}) {
      xmin = std::min(xmin, p->x), xmax = std::max(xmax, p->x);
      ymin = std::min(ymin, p->y), ymax = std::max(ymax, p->y);
    }
  }
  const double m = 1.5 * span_radius + 2.0;
  g.x_lo = std::max(g.x_lo, clamp_int(std::floor(xmin - m), res));
  g.x_hi = std::min(g.x_hi, clamp_int(std::ceil(xmax + m), res));
  g.y_lo = std::max(g.y_lo, clamp_int(std::floor(ymin - m), res));
  g.y_hi = std::min(g.y_hi, clamp_int(std::ceil(ymax + m), res));
  if (g.y_lo > g.y_hi || g.x_lo > g.x_hi) return false;
  const DVec3 &s0 = f.s[0], &s1 = f.s[1], &s2 = f.s[2];
  g.orient = (s1.x - s0.x) * (s2.y - s0.y) - (s1.y - s0.y) * (s2.x - s0.x) >= 0.0 ? 1u : 0u;
  return true;
}

/// Distance from (px, py) to the segment a → b.
double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay, len2 = ex * ex + ey * ey;
  const double t =
      len2 > 0.0 ? std::clamp(((px - ax) * ex + (py - ay) * ey) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(px - ax - t * ex, py - ay - t * ey);
}

/// The tiles a face can write: those in its cover's texel box whose centre lies near enough to a
/// silhouette edge that one of its texel centres can be in the edge's span (the rectangle reaching
/// `radius` past the segment: within radius·√2 of it) — a conservative test; the shader decides.
void bin_face(const FaceGpu& g, uint32_t index, double radius, int tiles_x,
              std::vector<std::vector<uint32_t>>& bins) {
  const double reach = 1.5 * radius + 1.0 + 0.5 * kTile * 1.5;  // + half the tile's diagonal
  for (int ty = g.y_lo / kTile; ty <= g.y_hi / kTile; ++ty)
    for (int tx = g.x_lo / kTile; tx <= g.x_hi / kTile; ++tx) {
      const double cx = (tx + 0.5) * kTile, cy = (ty + 0.5) * kTile;
      bool near = false;
      for (int c = 0; c < 3 && !near; ++c) {
        const int n = (c + 1) % 3;
        near = (g.mask & (1u << c)) &&
               segment_distance(cx, cy, g.sx[c], g.sy[c], g.sx[n], g.sy[n]) <= reach;
      }
      if (near) bins[static_cast<size_t>(ty) * tiles_x + tx].push_back(index);
    }
}

void put3(double* d, const DVec3& v) {
  for (int c = 0; c < 3; ++c) d[c] = v[c];
}

/// The faces on the GPU, binned to the kTile² tiles they can write: the tiles with faces (one
/// workgroup each) and their bins, in face order (so that the LESSEQUAL merge sees the CPU's).
struct TileBins {
  std::vector<FaceGpu> faces;
  std::vector<uint32_t> tiles, begin{0}, entries;
  uint32_t longest = 0;  // the longest bin
  int tiles_x = 0;       // tiles per side
};

TileBins bin_faces(const std::vector<silmap::SilFace>& faces, int res, double span_radius) {
  TileBins out;
  out.tiles_x = (res + kTile - 1) / kTile;
  std::vector<std::vector<uint32_t>> bins(static_cast<size_t>(out.tiles_x) * out.tiles_x);
  out.faces.reserve(faces.size());
  for (const silmap::SilFace& f : faces) {
    FaceGpu gf;
    if (!to_gpu(f, res, span_radius, gf)) continue;
    bin_face(gf, static_cast<uint32_t>(out.faces.size()), span_radius, out.tiles_x, bins);
    out.faces.push_back(gf);
  }
  for (size_t t = 0; t < bins.size(); ++t) {
    if (bins[t].empty()) continue;
    out.tiles.push_back(static_cast<uint32_t>(t));
    out.entries.insert(out.entries.end(), bins[t].begin(), bins[t].end());
    out.begin.push_back(static_cast<uint32_t>(out.entries.size()));
    out.longest = std::max(out.longest, static_cast<uint32_t>(bins[t].size()));
  }
  return out;
}

/// Stage 2's result: the band, the silhouette faces binned to tiles, the eq. 4 table and the
/// lookup's parameters.
struct Silhouettes {
  double half_band = 0.0, span_radius = 0.0;
  size_t tam_faces = 0;
  silmap::SilhouetteLayer counts;
  TileBins bins;
  std::vector<float> table;  // silmap::GradientTable::values()
  LookupParams prm{};
};

/// silmap_lookup.comp's parameters: the depth map's projection and biases, the band and the
/// table's shape.
LookupParams lookup_params(const DepthMapView& view, uint32_t res, const DepthMapSettings& map,
                           double half_band, double radius, const silmap::GradientTable& table) {
  const Projection& proj = view.proj;
  LookupParams prm{};
  put3(prm.eye, proj.eye), put3(prm.right, proj.right), put3(prm.up, proj.up);
  put3(prm.forward, proj.forward);
  prm.tan_half_x = proj.tan_half_x, prm.tan_half_y = proj.tan_half_y;
  prm.texel_tan = view.texel_tan, prm.resolution = res;
  prm.bias = map.bias, prm.slope_bias = map.slope_bias;
  prm.half_band = half_band, prm.radius = radius, prm.row_width_max = table.row_width_max();
  for (int k = 0; k < 4; ++k) {
    const double a = kPi * (0.25 + 0.5 * k);
    prm.cos_k[k] = std::cos(a), prm.sin_k[k] = std::sin(a);
  }
  prm.rows = table.rows();
  return prm;
}

/// Stage 3's device outputs: the silhouette layer (edge distance and depth per texel), the
/// count of texels visited and each active pixel's visibility.
struct LayerOutputs {
  Buffer distance, depth, visited, vis;
};

class SilhouetteMapVk final : public ShadowMethod {
 public:
  SilhouetteMapVk(Backend& backend, const MethodOptions& o)
      : backend_(backend),
        map_(DepthMapSettings::from(o)),
        soft_(o.get_choice("mode") == "soft"),
        width_(o.get_real("width")),
        aa_(o.get_real("aa_width")),
        offset_(o.get_real("offset")),
        max_band_(o.get_real("max_band")) {}

  /// The TAM depends on the meshes alone: built once per scene (the CPU method rebuilds it in
  /// every compute()).
  void prepare(const Scene& scene) override {
    tam_ = silmap::build_tam(scene);
    prepared_ = true;
  }

  Visibility compute(const ShadowContext& ctx) override {
    VulkanContext& vk = backend_.context();
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);

    ScopedStage upload_stage(vis.times, "wall_upload");
    const auto [active, cover, points] = lookup_points(g, ctx.receivers);
    std::deque<Buffer> keep;  // what the submissions read, kept to the end
    std::deque<Image2D> images;
    keep.push_back(vk.upload(points));
    const Buffer& point_buf = keep.back();
    const Buffer min_buf(vk, sizeof(uint32_t), Memory::device);
    upload_stage.stop();

    const double radius = soft_ ? silmap::light_radius(ctx.light) : 0.0;
    float min_depth = kInfinity;
    const GpuDepthMap map =
        depth_map(vk, ctx, cover, radius, min_buf, keep, images, min_depth, vis.times);
    const Silhouettes sil = silhouettes(ctx, map, radius, min_depth, vis.times);
    const LayerOutputs out = silhouettes_and_lookup(
        vk, sil, map, point_buf, static_cast<uint32_t>(active.size()), keep, vis.times);

    ScopedStage readback_stage(vis.times, "wall_readback");
    const std::vector<float> v = vk.download<float>(out.vis, active.size());
    for (size_t a = 0; a < active.size(); ++a) vis.lit[active[a]] = v[a];
    const uint32_t texels_visited = vk.download<uint32_t>(out.visited, 1)[0];
    readback_stage.stop();
    vis.counters["tam_faces"] = static_cast<double>(sil.tam_faces);
    vis.counters["silhouette_faces"] = static_cast<double>(sil.counts.silhouette_faces);
    vis.counters["corrected_faces"] = static_cast<double>(sil.counts.corrected_faces);
    vis.counters["silhouette_texels"] = static_cast<double>(texels_visited);
    vis.counters["duplicate_faces"] = static_cast<double>(sil.counts.duplicate_faces);
    vis.counters["half_band_texels"] = sil.half_band;
    vis.counters["map_texel_tan"] = map.view.texel_tan;
    return vis;
  }

 private:
  /// 1. The depth map and, in soft mode (radius > 0), its nearest depth for the band, into
  /// `min_depth` (left at kInfinity without a caster).
  GpuDepthMap depth_map(VulkanContext& vk, const ShadowContext& ctx, std::span<const Vec3> cover,
                        double radius, const Buffer& min_buf, std::deque<Buffer>& keep,
                        std::deque<Image2D>& images, float& min_depth, StageTimes& times) {
    ScopedStage stage(times, "wall_depth_map");
    CommandList cl(vk);
    DepthMapSpec spec;
    spec.resolution = map_.resolution;
    spec.faces = map_.faces;
    GpuDepthMap map = record_depth_map(vk, backend_.depth_pipeline(), cl, ctx.scene,
                                       hard_shadow_point(ctx.light), cover, spec, keep, images);
    cl.mark("depth_map");
    const uint32_t res = static_cast<uint32_t>(map.resolution), texels = res * res;
    if (radius > 0.0) {
      cl.fill(min_buf, 0x7f7fffffu);  // FLT_MAX
      cl.barrier();
      cl.dispatch(backend_.programs().get(Shader::depth_min),
                  MinPush{map.depth.address(), min_buf.address(), texels},
                  (texels + kMinTexelsPerThread - 1) / kMinTexelsPerThread);
      cl.barrier();
      cl.mark("min_depth");
    }
    cl.submit(&times);
    if (radius > 0.0) {
      const float m = vk.download<float>(min_buf, 1)[0];
      if (m < kEmptyDepth) min_depth = m;  // FLT_MAX: no caster in the map
    }
    return map;
  }

  /// 2. Host: the band, the silhouette faces (the TAM's, eq. 1, the §2.1.1 correction and the
  /// eq. 2 scaling), their tile bins, and the eq. 4 table.
  Silhouettes silhouettes(const ShadowContext& ctx, const GpuDepthMap& map, double radius,
                          float min_depth, StageTimes& times) {
    ScopedStage stage(times, "wall_silhouette_faces");
    Silhouettes out;
    const int res = map.resolution;
    double max_width = 0.0;
    const double zmax =
        radius > 0.0 && min_depth < kInfinity ? silmap::receivers_zmax(ctx, map.view.proj) : 0.0;
    silmap::silhouette_band(width_, max_band_, radius, min_depth, zmax, map.view.texel_tan,
                            out.half_band, max_width);
    if (!prepared_) tam_ = silmap::build_tam(ctx.scene);  // compute() without prepare()
    out.tam_faces = tam_.size();
    const std::vector<silmap::SilFace> faces =
        silmap::silhouette_faces(tam_, map.view.proj, res, out.half_band, out.counts);
    out.span_radius = out.half_band + 1.0;
    out.bins = bin_faces(faces, res, out.span_radius);
    const double row_max = std::max(1.0, std::min(max_width, 2.0 * out.half_band) * 0.5);
    const silmap::GradientTable table(radius > 0.0 ? silmap::kSoftRows : 1, out.half_band, row_max,
                                      aa_, offset_);
    out.table = table.values();
    out.prm =
        lookup_params(map.view, static_cast<uint32_t>(res), map_, out.half_band, radius, table);
    return out;
  }

  /// 3. GPU: the silhouette layer, in chunks of the longest bin (llvmpipe's loop limit), then the
  /// lookup of eq. 4 for the `n` points in point_buf.
  LayerOutputs silhouettes_and_lookup(VulkanContext& vk, const Silhouettes& sil,
                                      const GpuDepthMap& map, const Buffer& point_buf, uint32_t n,
                                      std::deque<Buffer>& keep, StageTimes& times) {
    ScopedStage stage(times, "wall_gpu");
    const TileBins& bins = sil.bins;
    const uint32_t res = static_cast<uint32_t>(map.resolution), texels = res * res;
    keep.push_back(vk.upload(bins.faces.empty() ? std::vector<FaceGpu>(1) : bins.faces));
    const Buffer& face_buf = keep.back();
    keep.push_back(vk.upload(bins.tiles.empty() ? std::vector<uint32_t>(1) : bins.tiles));
    const Buffer& tile_buf = keep.back();
    keep.push_back(vk.upload(bins.begin));
    const Buffer& begin_buf = keep.back();
    keep.push_back(vk.upload(bins.entries.empty() ? std::vector<uint32_t>(1) : bins.entries));
    const Buffer& entry_buf = keep.back();
    keep.push_back(vk.upload(sil.table));
    const Buffer& table_buf = keep.back();
    keep.push_back(vk.upload(&sil.prm, sizeof(sil.prm)));
    const Buffer& prm_buf = keep.back();
    LayerOutputs out{Buffer(vk, size_t{texels} * 4, Memory::device),
                     Buffer(vk, size_t{texels} * 4, Memory::device), Buffer(vk, 4, Memory::device),
                     Buffer(vk, std::max<size_t>(n, 1) * sizeof(float), Memory::device)};
    CommandList cl(vk);
    cl.fill(out.distance, 0);
    cl.fill(out.depth, 0x7f800000u);  // +inf: no silhouette yet
    cl.fill(out.visited, 0);
    cl.barrier();
    const uint32_t chunk = entry_chunk(vk);
    const uint32_t tile_count = static_cast<uint32_t>(bins.tiles.size());
    for (uint32_t first = 0; first < bins.longest; first += chunk) {
      cl.dispatch(backend_.programs().get(Shader::silmap_layer),
                  LayerPush{face_buf.address(), tile_buf.address(), begin_buf.address(),
                            entry_buf.address(), out.distance.address(), out.depth.address(),
                            out.visited.address(), sil.half_band, sil.span_radius, res,
                            static_cast<uint32_t>(bins.tiles_x), tile_count, first, chunk},
                  uint64_t{tile_count} * kTile * kTile);
      cl.barrier();
    }
    cl.mark("silhouettes");
    cl.dispatch(backend_.programs().get(Shader::silmap_lookup),
                LookupPush{prm_buf.address(), point_buf.address(), map.depth.address(),
                           out.distance.address(), out.depth.address(), table_buf.address(),
                           out.vis.address(), n},
                n);
    cl.barrier();
    cl.mark("lookup");
    cl.submit(&times);
    return out;
  }
  Backend& backend_;
  DepthMapSettings map_;
  bool soft_;
  double width_, aa_, offset_, max_band_;
  std::vector<silmap::TamFace> tam_;
  bool prepared_ = false;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_silhouette_map_vk(Backend& backend,
                                                       const MethodOptions& options) {
  if (!backend.context().has_float64())
    throw Error("silhouette_map on vulkan needs shaderFloat64, which " +
                backend.context().device_name() + " lacks");
  return std::make_unique<SilhouetteMapVk>(backend, options);
}

}  // namespace penumbra::gpu
