#include "penumbra/gpu/wedge_pixels.hpp"

#include "penumbra/gpu/wedge_data.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/wedges/pass.hpp"

namespace penumbra::gpu {

namespace {
constexpr uint32_t kValid = 1, kRound = 2, kTauNeg = 4;  // shaders/dcs.glsl
}  // namespace

std::vector<WedgePixelGpu> wedge_pixels(const ShadowContext& ctx, const Light& light, int tiles_x) {
  const GBuffer& g = ctx.gbuffer;
  const bool per_pixel_frame = frame_depends_on_receiver(light);
  const LightFrame fixed_frame = light_frame(light, light.center);
  std::vector<WedgePixelGpu> pixels;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (ctx.receivers[i] != kActive) continue;
    const int x = static_cast<int>(i % g.width), y = static_cast<int>(i / g.width);
    WedgePixelGpu& px = pixels.emplace_back();
    px = {};
    px.pixel = static_cast<uint32_t>(i);
    px.tile = static_cast<uint32_t>((y / wedge_pass::kTile) * tiles_x + x / wedge_pass::kTile);
    const wedge_pass::PixelLight pl(light, fixed_frame, per_pixel_frame, g.shadow_origin(i));
    if (!pl.valid()) continue;
    const LightFrame f = per_pixel_frame ? light_frame(light, g.shadow_origin(i)) : fixed_frame;
    const LightProjection& lp = pl.projection();
    put3(px.p, pl.point());
    put3(px.to_u, lp.to_u), put3(px.to_v, lp.to_v), put3(px.to_w, lp.to_w);
    px.inv_area = 1.0 / f.uv_area();
    px.flags = kValid | (pl.round() ? kRound : 0) | (pl.tau() < 0.0 ? kTauNeg : 0);
  }
  return pixels;
}

}  // namespace penumbra::gpu
