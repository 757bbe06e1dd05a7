// GEARS's per-frame set-up before its grid passes [Wang 2014 §3.1]: the pixel samples and the
// occluders in light space, the light samples every pixel shares, and the pixels no occluder's
// box can shadow.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/scene/light.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"

namespace penumbra {
struct ShadowContext;
}

namespace penumbra::gears {

/// The method's options (the registry's declarations: gears.cpp).
struct Options {
  int grid = 0;  // 0: grid_resolution's choice for the image
  bool lut = false;
  int lut_resolution = 256;
  AssignOptions assign;
  float eye_distance = 1.0f;
  int chunk = 32;
  bool pixel_cull = true;
  int group = 8;
  int long_chunk = 4;
  bool hidden_cull = true;
  bool deepest_first = true;
  bool box_cull = true;
  bool solid_cull = true;
};

/// The active pixels' shadow origins and the shadow-casting triangles in one light space.
struct LightSetup {
  std::vector<uint32_t> active;  // the kActive pixels, in index order
  uint64_t back_facing = 0;      // pixels of class kBackFacing (not computed)
  LightFrame frame0;             // the light's frame from a point below its centre
  Vec3 toward{0.0f};             // world direction the light space faces
  LightSpace space;
  std::vector<Vec3> p_light;  // per active pixel: its shadow origin in light space
  TriangleSoup soup;
  bool any_translucent = false;  // some occluder is alpha-textured or semi-opaque
  bool any_semi_opaque = false;  // some occluder has transmittance > 0
};

LightSetup setup_light_space(const ShadowContext& ctx);

/// What the pixels share of the light samples (grid-based patterns; for per-pixel patterns only
/// the unit square and every sample emitting), and the light points the volumes extrude through.
struct SharedSamples {
  std::vector<Vec2> uv;              // the shared light-uv positions
  std::vector<float> u, v;           // the same, split (the per-sample rasterizer reads arrays)
  Vec2 uv_lo{0.0f}, uv_hi{1.0f};     // their bounding box
  std::vector<uint64_t> emit_words;  // bit s: shared sample s emits (round lights mask corners)
  int emit_count = 0;
  std::vector<Vec3> corners;  // light-space extrusion corners (1 point, 4 or 8 for a sphere)
  float light_max_z = 0.0f;   // a sphere's radius in light-space depth units
};

SharedSamples shared_samples(const ShadowContext& ctx, const LightSetup& setup);

/// Per active pixel: 0 where no shadow-casting mesh's light-space box can shadow it (most of a
/// frame, for a rectangle or disk light with shared samples), 1 elsewhere; all 1 where the cull
/// does not apply (`enabled` false, per-pixel samples, point and sphere lights, over 256 meshes).
std::vector<uint8_t> box_cull_pixels(const ShadowContext& ctx, const LightSetup& setup,
                                     const SharedSamples& samples, bool enabled);

}  // namespace penumbra::gears
