#include "penumbra/gpu/depth_pass.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/graphics.hpp"
#include "penumbra/gpu/shaders.hpp"
#include "penumbra/render/receivers.hpp"

namespace penumbra::gpu {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

// depth_map.vert (hardware coverage).
struct DepthPush {
  VkDeviceAddress vertices;
  uint64_t padding;  // std430: the vec4s start at 16
  float eye[4];      // xyz, near
  float right[4];    // xyz, tan_half_x
  float up[4];       // xyz, tan_half_y
  float forward[4];  // xyz, unused
};
static_assert(sizeof(DepthPush) == 80);

// The exact pass (depth_exact.glsl).
struct ExactPush {
  VkDeviceAddress polys;
  float resolution;
  float depth_scale;
};

// depth_setup.comp's View (scalar layout).
struct SetupView {
  double eye[3], right[3], up[3], forward[3];
  double tan_half_x, tan_half_y, width, height;  // clip.glsl's ClipView
  double near;
  int32_t faces;
};

struct SetupPush {
  VkDeviceAddress vertices, view, polys;
  uint32_t n;
};

// depth_exact.glsl's ScreenPoly (scalar layout: 9 dvec3, 5 ints, padded to 8).
constexpr size_t kScreenPolyBytes = 240;

// A power of two 2^-k with 2^k above every view depth a caster point can have (its distance from
// the eye), so depth × scale lies in (0, 1) and is exact.
float depth_scale(const Scene& scene, const Vec3& eye) {
  const Bounds3 b = scene.bounds();
  double far = 1.0;
  for (int c = 0; c < 8 && !b.empty(); ++c) {
    const DVec3 corner((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y,
                       (c & 4) ? b.hi.z : b.lo.z);
    far = std::max(far, glm::length(corner - DVec3(eye)));
  }
  int exponent = 0;
  std::frexp(2.0 * far, &exponent);
  return static_cast<float>(std::ldexp(1.0, -std::min(exponent, 120)));
}

void record_hardware_draw(VkCommandBuffer cmd, const DepthPipeline& pipe, const GpuDepthMap& map,
                          const Buffer& vertices) {
  const Projection& pr = map.view.proj;
  DepthPush push{};
  push.vertices = vertices.address();
  const float near = static_cast<float>(map.view.near);
  auto put = [](float* d, const DVec3& v, double w) {
    d[0] = static_cast<float>(v.x), d[1] = static_cast<float>(v.y), d[2] = static_cast<float>(v.z);
    d[3] = static_cast<float>(w);
  };
  put(push.eye, pr.eye, near);
  put(push.right, pr.right, pr.tan_half_x);
  put(push.up, pr.up, pr.tan_half_y);
  put(push.forward, pr.forward, 0.0);
  vkCmdPushConstants(cmd, pipe.layout(), kGraphicsPushStages, 0, sizeof(push), &push);
  if (map.triangles) vkCmdDraw(cmd, static_cast<uint32_t>(map.triangles * 3), 1, 0, 0);
}

/// Records depth_setup.comp: every caster's screen polygon and pixel box (exact pass); returns
/// their buffer's address (0 without casters).
VkDeviceAddress setup_polys(VulkanContext& ctx, const DepthPipeline& pipe, CommandList& cl,
                            const GpuDepthMap& map, const Buffer& vertices,
                            const DepthMapSpec& spec, std::deque<Buffer>& keep) {
  if (!map.triangles) return 0;
  const Projection& pr = map.view.proj;
  SetupView v{};
  for (int c = 0; c < 3; ++c)
    v.eye[c] = pr.eye[c], v.right[c] = pr.right[c], v.up[c] = pr.up[c],
    v.forward[c] = pr.forward[c];
  v.tan_half_x = pr.tan_half_x, v.tan_half_y = pr.tan_half_y;
  v.width = v.height = map.resolution;
  v.near = map.view.near;
  v.faces = spec.faces == FaceSelect::front ? 0 : spec.faces == FaceSelect::back ? 1 : 2;
  keep.push_back(ctx.upload(&v, sizeof(v)));
  const VkDeviceAddress view = keep.back().address();
  keep.emplace_back(ctx, map.triangles * kScreenPolyBytes, Memory::device);
  const VkDeviceAddress polys = keep.back().address();
  cl.dispatch(pipe.setup(),
              SetupPush{vertices.address(), view, polys, static_cast<uint32_t>(map.triangles)},
              map.triangles);
  cl.barrier();
  return polys;
}

struct RasterPush {
  VkDeviceAddress polys, depth;
  uint32_t triangles;
  int32_t resolution;
};

/// Records depth_raster.comp into map.depth: a workgroup (kGroupSize threads) per caster.
void record_compute_raster(CommandList& cl, const DepthPipeline& pipe, const GpuDepthMap& map,
                           VkDeviceAddress polys) {
  uint32_t empty_bits = 0;
  std::memcpy(&empty_bits, &kEmptyDepth, sizeof(empty_bits));
  cl.fill(map.depth, empty_bits);
  cl.barrier();
  if (!map.triangles) return;
  cl.dispatch(
      pipe.raster(),
      RasterPush{polys, map.depth.address(), static_cast<uint32_t>(map.triangles), map.resolution},
      static_cast<uint64_t>(map.triangles) * kGroupSize);
  cl.barrier();
}

}  // namespace

DepthPipeline::DepthPipeline(VulkanContext& ctx, bool exact, RasterPath raster)
    : exact_(exact && ctx.has_float64()) {
  if (exact_) setup_ = std::make_unique<ComputePipeline>(ctx, spirv(Shader::depth_setup));
  if (exact_ && raster == RasterPath::compute) {
    raster_ = std::make_unique<ComputePipeline>(ctx, spirv(Shader::depth_raster));
    return;
  }
  GraphicsDesc d;
  d.vert = exact_ ? Shader::depth_map_exact_vert : Shader::depth_map_vert;
  d.frag = exact_ ? Shader::depth_map_exact_frag : Shader::depth_map_frag;
  d.push_bytes = sizeof(DepthPush);
  d.color = kColorFormat;
  d.depth = kDepthFormat;
  // Hardware pass: reversed z, depth = near / view depth. Exact pass: depth = view depth × 2^-k.
  d.depth_op = exact_ ? VK_COMPARE_OP_LESS : VK_COMPARE_OP_GREATER;
  graphics_ = std::make_unique<GraphicsPipeline>(ctx, d);
}

DepthPipeline::~DepthPipeline() = default;

GpuDepthMap record_depth_map(VulkanContext& ctx, DepthPipeline& pipe, CommandList& cl,
                             const Scene& scene, const Vec3& light_point,
                             std::span<const Vec3> cover, const DepthMapSpec& spec,
                             std::deque<Buffer>& keep, std::deque<Image2D>& images) {
  GpuDepthMap out;
  out.view = fit_depth_map_view(scene, light_point, cover, spec.resolution);
  out.resolution = spec.resolution;
  const int res = spec.resolution;
  // The casters' triangles, world space (vertex pulling: 3 vec4 per triangle).
  std::vector<float> verts;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.casts_shadows) continue;
    for (size_t t = 0; t < mesh.triangle_count(); ++t)
      for (int c = 0; c < 3; ++c) {
        const Vec3 p = mesh.vertex(t, c);
        verts.insert(verts.end(), {p.x, p.y, p.z, 1.0f});
      }
  }
  out.triangles = verts.size() / 12;
  keep.push_back(ctx.upload(verts));
  const Buffer& vbuf = keep.back();
  out.depth = Buffer(ctx, static_cast<size_t>(res) * res * sizeof(float), Memory::device);

  if (pipe.compute()) {
    record_compute_raster(cl, pipe, out, setup_polys(ctx, pipe, cl, out, vbuf, spec, keep));
    return out;
  }
  images.emplace_back(ctx, res, res, kColorFormat,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                      VK_IMAGE_ASPECT_COLOR_BIT);
  const Image2D& color = images.back();
  images.emplace_back(ctx, res, res, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT);
  const Image2D& depth = images.back();

  const bool exact = pipe.exact();
  const VkDeviceAddress polys = exact ? setup_polys(ctx, pipe, cl, out, vbuf, spec, keep) : 0;

  VkCommandBuffer cmd = cl.cmd();
  begin_rendering(cmd, color, kEmptyDepth, &depth, exact ? 1.0f : 0.0f, res, res);  // far: empty
  // FaceSelect::front keeps triangles whose normal cross(p1−p0, p2−p0) faces the light: after the
  // y flip of depth_map.vert those have the winding Vulkan calls counter-clockwise.
  vkCmdSetFrontFace(cmd, VK_FRONT_FACE_COUNTER_CLOCKWISE);
  // The exact pass culls in depth_setup.comp (its boxes have no winding).
  vkCmdSetCullMode(cmd, exact                             ? VK_CULL_MODE_NONE
                        : spec.faces == FaceSelect::front ? VK_CULL_MODE_BACK_BIT
                        : spec.faces == FaceSelect::back  ? VK_CULL_MODE_FRONT_BIT
                                                          : VK_CULL_MODE_NONE);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe.handle());
  if (exact) {
    const ExactPush push{polys, static_cast<float>(res), depth_scale(scene, light_point)};
    vkCmdPushConstants(cmd, pipe.layout(), kGraphicsPushStages, 0, sizeof(push), &push);
    if (out.triangles) vkCmdDraw(cmd, static_cast<uint32_t>(out.triangles * 6), 1, 0, 0);
  } else {
    record_hardware_draw(cmd, pipe, out, vbuf);
  }
  end_rendering_into(cmd, color, res, res, out.depth);
  cl.barrier();
  return out;
}

LookupPoints lookup_points(const GBuffer& g, const Image<uint8_t>& receivers) {
  LookupPoints out;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (receivers[i] != kActive) continue;
    out.active.push_back(static_cast<uint32_t>(i));
    const Vec3 p = g.shadow_origin(i), n = g.geo_normal[i];
    out.cover.push_back(p);
    out.points.insert(out.points.end(), {p.x, p.y, p.z, 0.0f, n.x, n.y, n.z, 0.0f});
  }
  return out;
}

}  // namespace penumbra::gpu
