// `shadow_volume` on Vulkan [Forest 2008 §2.2.1, §3.3.1, App. 3.A]: deferred z-fail counting with
// the graphics pipeline.
//   host:  the summed volume's faces, built as the CPU method builds them (shadow_volume.cpp):
//          per caster triangle facing the light its near cap and its far cap at infinity, per
//          silhouette edge (silhouettes.hpp, signed multiplicity) its quad extruded to infinity;
//          per pixel the exact shadow origin relative to the camera (shadow_volume_pixels).
//   GPU:   volume_setup.comp: each face's screen polygon, cull, orientation, edge planes through
//          the camera and tie bits, in double; volume.vert/.frag: each face drawn as a rectangle
//          holding its candidate pixels, the fragment shader applies the CPU's exact test at the
//          pixel's shadow origin (inside the face's cone, face behind the receiver) and emits the
//          face's signed weight; additive blending into an R32F target sums the counts.
//   host:  count > 0 → shadowed.
// The counts are the CPU's exactly: both run the same double-precision tests on the same points;
// the rasterizer only proposes pixels (a superset), it never decides one.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <initializer_list>
#include <optional>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/graphics.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::gpu {

namespace {

// volume_setup.comp's FaceIn (scalar layout).
struct FaceIn {
  uint32_t ids[4];
  int32_t n, weight, has_plane;
  double plane_n[3];
  double plane_k;
};
static_assert(sizeof(FaceIn) == 64);

// volume_setup.comp's View: clip.glsl's ClipView, the light point, near, guard, margin.
struct VolumeView {
  double eye[3], right[3], up[3], forward[3];
  double tan_half_x, tan_half_y, width, height;
  double light[3];
  double near, guard, margin;
  double grow;  // of the candidate rectangles, pixels
};

// volume.glsl's VolumeFace: 4 + 1 dvec3, a double, 4 ints, 4 vec2.
constexpr size_t kVolumeFaceBytes = 5 * 24 + 8 + 16 + 32;

struct CountPush {
  VkDeviceAddress faces, q, counts;
  uint32_t n, width, height;
};

struct SetupPush {
  VkDeviceAddress positions, view, faces, out_faces;
  uint32_t n;
};
struct DrawPush {
  VkDeviceAddress faces, q;
  float size[2];
};

void put3(double* d, const DVec3& v) {
  for (int c = 0; c < 3; ++c) d[c] = v[c];
}

/// The summed volume's faces for light point L seen from camera C (shadow_volume.cpp's loops).
struct Volume {
  std::vector<float> positions;  // welded caster vertices, xyzw
  std::vector<FaceIn> faces;
  size_t silhouette_edges = 0;
};

Volume build_volume(const Scene& scene, const DVec3& C, const Vec3& light_point) {
  Volume v;
  std::vector<DVec3> pos;
  const DVec3 L(light_point);
  auto add = [&](std::initializer_list<uint32_t> ids, int32_t weight, const DVec3* plane_n,
                 double plane_k) {
    FaceIn f{};
    int i = 0;
    for (uint32_t id : ids) f.ids[i++] = id;
    f.n = i;
    f.weight = weight;
    f.has_plane = plane_n != nullptr;
    if (plane_n) put3(f.plane_n, *plane_n), f.plane_k = plane_k;
    v.faces.push_back(f);
  };
  for (const Mesh& m : scene.meshes) {
    if (!m.casts_shadows || m.triangles.empty()) continue;
    const MeshEdges edges = build_mesh_edges(m);
    const uint32_t base = static_cast<uint32_t>(pos.size());
    for (const Vec3& p : m.positions) {
      pos.push_back(DVec3(p));
      v.positions.insert(v.positions.end(), {p.x, p.y, p.z, 1.0f});
    }
    const std::vector<int8_t> sides = face_sides(m, edges, light_point);
    const std::vector<SilhouetteEdge> silhouette = silhouette_from_sides(edges, sides);
    v.silhouette_edges += silhouette.size();
    for (size_t f = 0; f < edges.faces.size(); ++f) {
      const int side = sides[f];
      if (side == 0) continue;
      const auto& w = edges.faces[f];
      // Near cap oriented toward the light, far cap the reverse at infinity.
      const uint32_t a = base + w[0], b = base + (side > 0 ? w[1] : w[2]),
                     c = base + (side > 0 ? w[2] : w[1]);
      const DVec3 n = glm::cross(pos[b] - pos[a], pos[c] - pos[a]);
      add({2 * a, 2 * b, 2 * c}, 1, &n, glm::dot(n, C - pos[a]));
      add({2 * a + 1, 2 * c + 1, 2 * b + 1}, 1, nullptr, 0.0);
    }
    for (const SilhouetteEdge& s : silhouette) {
      // The cap traverses from → to, so the side quad is (to, from, ∞from, ∞to).
      const uint32_t from = base + s.from, to = base + s.to;
      const DVec3 n = glm::cross(pos[from] - L, pos[to] - L);
      add({2 * to, 2 * from, 2 * from + 1, 2 * to + 1}, s.multiplicity, &n, glm::dot(n, C - L));
    }
  }
  return v;
}

/// How far the candidate rectangles grow around a face's polygon: a pixel counts only if its
/// shadow origin projects inside the polygon, at most `offset` pixels from its centre in x and y,
/// so √2 × offset (the CPU's margin rounds it up to whole pixels plus one, which would multiply
/// the fragments of small caps), plus a quarter pixel against the rasterizer's vertex snapping.
double candidate_growth(const ShadowVolumePixels& px, const GBuffer& g,
                        const Image<uint8_t>& receivers) {
  double offset = 0.0;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (receivers[i] != kActive) continue;
      const DVec4 c = px.proj.to_clip(DVec4(px.q[i] + px.proj.eye, 1.0));
      if (!(c.w > 0.0)) return px.margin * std::sqrt(2.0) + 0.25;
      const DVec3 s = px.proj.to_screen(c);
      offset = std::max({offset, std::abs(s.x - (x + 0.5)), std::abs(s.y - (y + 0.5))});
    }
  return std::min(offset, px.margin) * std::sqrt(2.0) + 0.25;
}

class ShadowVolumeVk final : public ShadowMethod {
 public:
  // The pipeline first: a device without shaderFloat64 fails here, before any work.
  explicit ShadowVolumeVk(Backend& backend) : backend_(backend) {
    if (backend_.raster_path() == RasterPath::graphics) {
      backend_.volume_pipeline();
    } else if (!backend_.context().has_float64()) {
      throw Error("shadow_volume on Vulkan needs shaderFloat64, which " +
                  backend_.context().device_name() + " lacks");
    }
  }

  Visibility compute(const ShadowContext& ctx) override {
    VulkanContext& vk = backend_.context();
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);

    auto t0 = std::chrono::steady_clock::now();
    const ShadowVolumePixels px = shadow_volume_pixels(ctx.scene.camera, g, ctx.receivers);
    if (!px.any_active) return vis;
    const Vec3 light_point = hard_shadow_point(ctx.light);
    const Volume volume = build_volume(ctx.scene, px.proj.eye, light_point);
    vis.times.add("edges", elapsed_ms(t0));
    vis.counters["silhouette_edges"] = static_cast<double>(volume.silhouette_edges);
    vis.counters["volume_faces"] = static_cast<double>(volume.faces.size());
    if (volume.faces.empty()) return vis;

    t0 = std::chrono::steady_clock::now();
    std::vector<double> q(4 * g.pixel_count(), 0.0);
    for (size_t i = 0; i < g.pixel_count(); ++i) {
      if (ctx.receivers[i] != kActive) continue;
      for (int c = 0; c < 3; ++c) q[4 * i + c] = px.q[i][c];
      q[4 * i + 3] = 1.0;
    }
    const Projection& pr = px.proj;
    VolumeView view{};
    put3(view.eye, pr.eye), put3(view.right, pr.right), put3(view.up, pr.up);
    put3(view.forward, pr.forward);
    view.tan_half_x = pr.tan_half_x, view.tan_half_y = pr.tan_half_y;
    view.width = pr.width, view.height = pr.height;
    put3(view.light, DVec3(light_point));
    view.near = px.near, view.guard = px.guard, view.margin = px.margin;
    view.grow = candidate_growth(px, g, ctx.receivers);
    std::deque<Buffer> keep;
    keep.push_back(vk.upload(volume.positions));
    const Buffer& positions = keep.back();
    keep.push_back(vk.upload(&view, sizeof(view)));
    const Buffer& view_buf = keep.back();
    keep.push_back(vk.upload(volume.faces));
    const Buffer& faces_in = keep.back();
    keep.push_back(vk.upload(q));
    const Buffer& q_buf = keep.back();
    const Buffer faces(vk, volume.faces.size() * kVolumeFaceBytes, Memory::device);
    // Floats from the blending, ints from the compute path's atomics: 4 bytes a pixel either way.
    const Buffer counts(vk, g.pixel_count() * sizeof(float), Memory::device);
    vis.times.add("wall_upload", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    CommandList cl(vk);
    const uint32_t n = static_cast<uint32_t>(volume.faces.size());
    cl.dispatch(
        backend_.programs().get(Shader::volume_setup),
        SetupPush{positions.address(), view_buf.address(), faces_in.address(), faces.address(), n},
        n);
    cl.barrier();
    cl.mark("setup");
    const bool compute = backend_.raster_path() == RasterPath::compute;
    std::optional<Image2D> target;
    if (compute) {
      record_count_compute(cl, faces, q_buf, g.width, g.height, n, counts);
    } else {
      target.emplace(vk, g.width, g.height, VK_FORMAT_R32_SFLOAT,
                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                     VK_IMAGE_ASPECT_COLOR_BIT);
      record_count(cl.cmd(), *target, faces, q_buf, g.width, g.height, n, counts);
    }
    cl.barrier();
    cl.mark("count");
    cl.submit(&vis.times);
    vis.times.add("wall_gpu", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    std::vector<float> c;
    if (compute) {
      const std::vector<int32_t> ints = vk.download<int32_t>(counts, g.pixel_count());
      c.assign(ints.begin(), ints.end());
    } else {
      c = vk.download<float>(counts, g.pixel_count());
    }
    size_t negative = 0, shadowed = 0;
    double sum = 0.0, largest = 0.0;
    for (size_t i = 0; i < g.pixel_count(); ++i) {
      if (ctx.receivers[i] != kActive) continue;
      sum += c[i];
      largest = std::max<double>(largest, c[i]);
      negative += c[i] < 0.0f;
      shadowed += c[i] > 0.0f;
      vis.lit[i] = c[i] > 0.0f ? 0.0f : 1.0f;
    }
    vis.times.add("wall_readback", elapsed_ms(t0));
    vis.counters["shadowed_pixels"] = static_cast<double>(shadowed);
    vis.counters["negative_count_pixels"] = static_cast<double>(negative);
    vis.counters["count_sum"] = sum;  // Σ count over the active pixels (tests: = the CPU's)
    vis.counters["count_max"] = largest;
    return vis;
  }

 private:
  /// The counting pass: every face's rectangle, blended additively into `target`, then copied into
  /// `counts` (row-major floats).
  void record_count(VkCommandBuffer cmd, const Image2D& target, const Buffer& faces,
                    const Buffer& q, int width, int height, uint32_t n, const Buffer& counts) {
    const GraphicsPipeline& pipe = backend_.volume_pipeline();
    // Orientation is the weight's sign, not the winding: nothing is culled.
    begin_rendering(cmd, target, 0.0f, nullptr, 0.0f, width, height);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe.handle());
    const DrawPush push{
        faces.address(), q.address(), {static_cast<float>(width), static_cast<float>(height)}};
    vkCmdPushConstants(cmd, pipe.layout(), kGraphicsPushStages, 0, sizeof(push), &push);
    vkCmdDraw(cmd, n * 6, 1, 0, 0);
    end_rendering_into(cmd, target, width, height, counts);
  }

  /// The counting pass in compute (volume_count.comp, RasterPath::compute): a workgroup per face,
  /// integer atomics into `counts`.
  void record_count_compute(CommandList& cl, const Buffer& faces, const Buffer& q, int width,
                            int height, uint32_t n, const Buffer& counts) {
    cl.fill(counts, 0u);
    cl.barrier();
    cl.dispatch(backend_.programs().get(Shader::volume_count),
                CountPush{faces.address(), q.address(), counts.address(), n,
                          static_cast<uint32_t>(width), static_cast<uint32_t>(height)},
                static_cast<uint64_t>(n) * kGroupSize);
  }

  Backend& backend_;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_shadow_volume_vk(Backend& backend, const MethodOptions&) {
  return std::make_unique<ShadowVolumeVk>(backend);
}

}  // namespace penumbra::gpu
