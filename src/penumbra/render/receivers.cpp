#include "penumbra/render/receivers.hpp"

#include "penumbra/core/parallel.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/scene/light.hpp"

namespace penumbra {

Image<uint8_t> classify_receivers(const GBuffer& g, const Light& light) {
  Image<uint8_t> classes(g.width, g.height, kBackground);
  // Built once where it does not depend on the receiver, not per pixel.
  const bool per_pixel_frame = frame_depends_on_receiver(light);
  const LightFrame fixed = light_frame(light, light.center);
  parallel_rows(g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      if (g.is_background(i)) continue;
      const Vec3 origin = g.shadow_origin(i);
      const LightFrame f = per_pixel_frame ? light_frame(light, origin) : fixed;
      const Vec3 corners[4] = {f.corner, f.corner + f.edge_u, f.corner + f.edge_v,
                               f.corner + f.edge_u + f.edge_v};
      bool front = false;
      for (const Vec3& c : corners) front = front || glm::dot(g.geo_normal[i], c - origin) > 0.0f;
      classes[i] = front ? kActive : kBackFacing;
    }
  });
  return classes;
}

}  // namespace penumbra
