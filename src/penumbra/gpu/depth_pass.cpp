#include "penumbra/gpu/depth_pass.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/shaders.hpp"

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
  double tan_half_x, tan_half_y, resolution, near;
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

constexpr VkShaderStageFlags kPushStages =
    VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

VkShaderModule make_module(VkDevice device, std::span<const uint32_t> code) {
  VkShaderModuleCreateInfo si{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  si.codeSize = code.size_bytes();
  si.pCode = code.data();
  VkShaderModule m = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device, &si, nullptr, &m), "vkCreateShaderModule");
  return m;
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                   VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  b.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
  b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  b.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, 0, 1, 0, 1};
  VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  di.imageMemoryBarrierCount = 1;
  di.pImageMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &di);
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
  vkCmdPushConstants(cmd, pipe.layout(), kPushStages, 0, sizeof(push), &push);
  if (map.triangles) vkCmdDraw(cmd, static_cast<uint32_t>(map.triangles * 3), 1, 0, 0);
}

}  // namespace

DepthPipeline::DepthPipeline(VulkanContext& ctx, bool exact)
    : device_(ctx.device()), exact_(exact && ctx.has_float64()) {
  const VkPushConstantRange range{kPushStages, 0, sizeof(DepthPush)};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device_, &li, nullptr, &layout_), "vkCreatePipelineLayout");

  VkShaderModule vert =
      make_module(device_, spirv(exact_ ? Shader::depth_map_exact_vert : Shader::depth_map_vert));
  VkShaderModule frag =
      make_module(device_, spirv(exact_ ? Shader::depth_map_exact_frag : Shader::depth_map_frag));
  if (exact_) setup_ = std::make_unique<ComputePipeline>(ctx, spirv(Shader::depth_setup));
  VkPipelineShaderStageCreateInfo stages[2] = {
      {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
      {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vert;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = frag;
  stages[1].pName = "main";
  VkPipelineVertexInputStateCreateInfo vi{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo ia{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rs{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  ds.depthWriteEnable = VK_TRUE;
  // Hardware pass: reversed z, depth = near / view depth. Exact pass: depth = view depth × 2^-k.
  ds.depthCompareOp = exact_ ? VK_COMPARE_OP_LESS : VK_COMPARE_OP_GREATER;
  VkPipelineColorBlendAttachmentState att{};
  att.colorWriteMask = VK_COLOR_COMPONENT_R_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = 1;
  cb.pAttachments = &att;
  const VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR,
                                VK_DYNAMIC_STATE_CULL_MODE, VK_DYNAMIC_STATE_FRONT_FACE};
  VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dy.dynamicStateCount = 4;
  dy.pDynamicStates = dyn;
  VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  ri.colorAttachmentCount = 1;
  ri.pColorAttachmentFormats = &kColorFormat;
  ri.depthAttachmentFormat = kDepthFormat;
  VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gi.pNext = &ri;
  gi.stageCount = 2;
  gi.pStages = stages;
  gi.pVertexInputState = &vi;
  gi.pInputAssemblyState = &ia;
  gi.pViewportState = &vp;
  gi.pRasterizationState = &rs;
  gi.pMultisampleState = &ms;
  gi.pDepthStencilState = &ds;
  gi.pColorBlendState = &cb;
  gi.pDynamicState = &dy;
  gi.layout = layout_;
  const VkResult r =
      vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &gi, nullptr, &pipeline_);
  vkDestroyShaderModule(device_, vert, nullptr);
  vkDestroyShaderModule(device_, frag, nullptr);
  if (r != VK_SUCCESS) {
    vkDestroyPipelineLayout(device_, layout_, nullptr);
    check(r, "depth-map pipeline creation");
  }
}

DepthPipeline::~DepthPipeline() {
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
}

Image2D::Image2D(VulkanContext& ctx, int width, int height, VkFormat format,
                 VkImageUsageFlags usage, VkImageAspectFlags aspect)
    : device_(ctx.device()) {
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = usage;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device_, &ii, nullptr, &image_), "vkCreateImage");
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device_, image_, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (ai.memoryTypeIndex == UINT32_MAX) ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, 0);
  if (vkAllocateMemory(device_, &ai, nullptr, &memory_) != VK_SUCCESS) {
    vkDestroyImage(device_, image_, nullptr);
    throw Error("vulkan: out of device memory for a " + std::to_string(width) + "x" +
                std::to_string(height) + " image");
  }
  check(vkBindImageMemory(device_, image_, memory_, 0), "vkBindImageMemory");
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = image_;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {aspect, 0, 1, 0, 1};
  check(vkCreateImageView(device_, &vi, nullptr, &view_), "vkCreateImageView");
}

Image2D::~Image2D() {
  vkDestroyImageView(device_, view_, nullptr);
  vkDestroyImage(device_, image_, nullptr);
  vkFreeMemory(device_, memory_, nullptr);
}

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

  images.emplace_back(ctx, res, res, kColorFormat,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                      VK_IMAGE_ASPECT_COLOR_BIT);
  const Image2D& color = images.back();
  images.emplace_back(ctx, res, res, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT);
  const Image2D& depth = images.back();

  const bool exact = pipe.exact();
  VkDeviceAddress polys = 0;
  if (exact && out.triangles) {
    const Projection& pr = out.view.proj;
    SetupView v{};
    for (int c = 0; c < 3; ++c)
      v.eye[c] = pr.eye[c], v.right[c] = pr.right[c], v.up[c] = pr.up[c],
      v.forward[c] = pr.forward[c];
    v.tan_half_x = pr.tan_half_x, v.tan_half_y = pr.tan_half_y;
    v.resolution = res;
    v.near = out.view.near;
    v.faces = spec.faces == FaceSelect::front ? 0 : spec.faces == FaceSelect::back ? 1 : 2;
    keep.push_back(ctx.upload(&v, sizeof(v)));
    const VkDeviceAddress view = keep.back().address();
    keep.emplace_back(ctx, out.triangles * kScreenPolyBytes, Memory::device);
    polys = keep.back().address();
    cl.dispatch(pipe.setup(),
                SetupPush{vbuf.address(), view, polys, static_cast<uint32_t>(out.triangles)},
                out.triangles);
    cl.barrier();
  }

  VkCommandBuffer cmd = cl.cmd();
  image_barrier(cmd, color.image(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  image_barrier(cmd, depth.image(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
  VkRenderingAttachmentInfo ca{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  ca.imageView = color.view();
  ca.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  ca.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  ca.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  ca.clearValue.color.float32[0] = kEmptyDepth;
  VkRenderingAttachmentInfo da{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  da.imageView = depth.view();
  da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  da.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  da.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  da.clearValue.depthStencil.depth = exact ? 1.0f : 0.0f;  // infinitely far
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {static_cast<uint32_t>(res), static_cast<uint32_t>(res)}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = 1;
  ri.pColorAttachments = &ca;
  ri.pDepthAttachment = &da;
  vkCmdBeginRendering(cmd, &ri);
  const VkViewport viewport{0.0f, 0.0f, static_cast<float>(res), static_cast<float>(res),
                            0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, {static_cast<uint32_t>(res), static_cast<uint32_t>(res)}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
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
    vkCmdPushConstants(cmd, pipe.layout(), kPushStages, 0, sizeof(push), &push);
    if (out.triangles) vkCmdDraw(cmd, static_cast<uint32_t>(out.triangles * 6), 1, 0, 0);
  } else {
    record_hardware_draw(cmd, pipe, out, vbuf);
  }
  vkCmdEndRendering(cmd);
  image_barrier(cmd, color.image(), VK_IMAGE_ASPECT_COLOR_BIT,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {static_cast<uint32_t>(res), static_cast<uint32_t>(res), 1};
  vkCmdCopyImageToBuffer(cmd, color.image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         out.depth.handle(), 1, &copy);
  cl.barrier();
  return out;
}

}  // namespace penumbra::gpu
