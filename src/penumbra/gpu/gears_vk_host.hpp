// `gears` on Vulkan, the host's part: the frame's light and samples as the CPU method plans them,
// the occluders in light space with the CPU's per-pixel cull data, each side's triangles in the
// CPU's depth order [Wang 2014 §4.2], and the masks read back and weighted as the CPU weights them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/render/visibility.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra::gpu::gears_host {

/// One side's occluders: 3 vec4 of vertices (the first's w: this side's nearest depth) and 6 vec4
/// per triangle: alpha data, transmittance, the slab bounds, the plane test's TrianglePlane (its
/// solid's index as the last float's bits).
constexpr size_t kTriInfo = 24;  // floats of alpha and cull data per triangle
struct SideTriangles {
  std::vector<float> tris, alpha;
};

/// The shadow-casting triangles in light space (3 vec4 each) and 3 vec4 of alpha data each
/// (texel offset, width, height, 1 = alpha-tested; uv0, uv1; uv2, transmittance), in the CPU's
/// order: shadow-casting meshes in order, each one's triangles in order.
struct Occluders {
  std::vector<float> tris, alpha;
  // 4 header words (the LUT's: table offset, angles, offsets, radius; 0: none), then the alpha
  // textures (1 where the texel blocks) and the LUT's table.
  std::vector<uint32_t> texels = std::vector<uint32_t>(4, 0);
  std::vector<uint32_t> mesh, prim;  // each triangle's mesh and index in it
  std::vector<uint8_t> opaque;
  bool semi_opaque = false;  // some occluder has transmittance > 0
  bool translucent = false;  // some occluder is semi-opaque or alpha-tested
};

Occluders gather_occluders(const Scene& scene, const gears::LightSpace& space);

/// The occluders as the CPU's TriangleSoup, for its plane and solid culls.
gears::TriangleSoup soup_of(const Occluders& o);

/// One side's cull data: the slab cull's light (for a flat light with shared samples, their box,
/// as the CPU's pass), the side's pixels' own slab bounds (pix's fifth vec4), and the triangles
/// in depth order with their slab bounds, planes (`soup`: none without the per-pixel culls) and
/// solids.
SideTriangles side_cull_data(const gears::GridCamera& cam, int side, bool shrink, Vec2 uv_lo,
                             Vec2 uv_hi, const std::vector<Vec3>& p_light, std::vector<float>& pix,
                             const Occluders& occ, const gears::TriangleSoup* soup,
                             const gears::Solids& solids);

/// The frame's light and samples, as the CPU method plans its passes: row spans for the regular
/// grid of shared samples (k ≤ 32), sample by sample otherwise (one sample at the light for a
/// point light), the LUT [Wang 2014 §4.3] where sample positions are shared.
struct Plan {
  bool sphere = false, point = false, per_pixel = false, use_lut = false, use_rows = false;
  int n = 0, k = 0, ns = 0;  // samples, grid side, samples the rasterizer tests
  uint32_t words = 0;        // 32-bit mask words per pixel of the per-sample rasterizer
  const Texture* emission = nullptr;
};

Plan plan_of(const ShadowContext& ctx, bool lut);

/// Per active pixel: its shadow origin in light space, and the 20 floats the shaders read — the
/// origin, the light's corner and edges from it (the sphere's silhouette disk seen from the
/// pixel), and its slab bounds (set per side).
void pixel_data(const ShadowContext& ctx, const gears::LightSpace& space, const Plan& plan,
                const std::vector<uint32_t>& active, std::vector<Vec3>& p_light,
                std::vector<float>& pix);

/// The light samples as the shaders read them: the shared positions and their box, the emitting
/// ones (per row for the row rasterizer, as bits of 64-bit words for the weighting), and the
/// per-sample rasterizer's positions and emitting bits — shared, or per pixel for per-pixel
/// patterns and a point light's one sample, as the CPU's work items set them.
struct SampleSetup {
  std::vector<Vec2> shared;
  Vec2 uv_lo{0.0f}, uv_hi{1.0f};  // per-pixel samples: the unit square holds them all
  std::vector<uint32_t> emit_rows;
  std::vector<uint64_t> emit_words;
  int emit_count = 0;
  std::vector<float> sample_uv;
  std::vector<uint32_t> emit_bits;
};

SampleSetup sample_setup(const ShadowContext& ctx, const Plan& plan, const LightFrame& frame0,
                         const std::vector<uint32_t>& active, int words64);

/// The CPU's EdgeLut for the shared samples, appended to `texels` after the alpha textures (its
/// header in texels[0..3]): 64-bit words as their two 32-bit halves, the same bits — 32-bit word w
/// holds samples 32·w … 32·w + 31 as the shader's masks.
void append_lut(std::span<const Vec2> shared, int resolution, std::vector<uint32_t>& texels);

/// The GPU's masks (`rows`: row spans or 32-bit words per pixel, then the semi-opaque per-sample
/// transmittances) into `masks`, and V weighted exactly as the CPU gears weights it.
void read_back(const ShadowContext& ctx, const Plan& plan, const SampleSetup& ss,
               const std::vector<uint32_t>& active, const std::vector<uint32_t>& rows,
               size_t mask_words, bool semi_opaque, SampleMasks& masks, Visibility& vis);

/// The light's corners in light space, for the extrusion (a sphere's bounding cube, z in units of
/// the light-space axis: ±r).
std::vector<Vec3> light_corners(const Plan& plan, float r);

/// The host's frame data for both sides of the light plane, as the CPU gears prepares it.
struct HostFrame {
  std::vector<uint32_t> active;  // the active pixels' indices
  LightFrame frame0;             // the light's frame seen from below its centre
  Vec3 toward{0.0f};             // light space's facing direction
  std::vector<Vec3> p_light;     // per active pixel: its shadow origin in light space
  std::vector<float> pix;        // per active pixel: the 20 floats of pixel_data
  Occluders occ;
  uint32_t tri_count = 0;
  gears::TriangleSoup soup;  // the occluders as the CPU's soup; empty without the per-pixel culls
  gears::Solids solids;
  float r = 0.0f;  // a sphere light's radius, in light-space z units
  std::vector<Vec3> corners;
  SampleSetup ss;
};

/// The active pixels and the direction light space faces: the light's emitting normal, or for
/// point and sphere lights toward the active pixels' box.
void active_pixels_and_toward(const ShadowContext& ctx, const Plan& plan, HostFrame& h);

/// The solids each pixel is certified outside of, for the CPU's solid cull: into pix as the w of
/// its w and eu vectors, as two 32-bit halves.
void mark_outside_solids(HostFrame& h);

}  // namespace penumbra::gpu::gears_host
