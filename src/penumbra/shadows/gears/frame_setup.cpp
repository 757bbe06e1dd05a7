#include "penumbra/shadows/gears/frame_setup.hpp"

#include <algorithm>
#include <atomic>

#include "penumbra/core/parallel.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra::gears {

namespace {

/// The shadow-casting triangles of the scene in light space, each mesh's from its offset on,
/// filled in parallel.
void fill_soup(const Scene& scene, const LightSpace& space, LightSetup& setup) {
  std::vector<size_t> first_of(scene.meshes.size() + 1, 0);
  std::vector<uint8_t> mesh_opaque(scene.meshes.size(), 0);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    first_of[m + 1] = first_of[m] + (mesh.casts_shadows ? mesh.triangle_count() : 0);
    if (!mesh.casts_shadows) continue;
    mesh_opaque[m] = scene.material_of(mesh).is_opaque() ? 1 : 0;
    setup.any_translucent |= !mesh_opaque[m];
    setup.any_semi_opaque |= scene.material_of(mesh).transmittance > 0.0f;
  }
  TriangleSoup& soup = setup.soup;
  soup.resize(first_of.back());
  parallel_chunks(soup.size(), 4096, [&](size_t b, size_t e) {
    size_t m = std::upper_bound(first_of.begin(), first_of.end(), b) - first_of.begin() - 1;
    for (size_t t = b; t < e; ++t) {
      while (t >= first_of[m + 1]) ++m;  // skips the meshes that cast no shadow
      const Mesh& mesh = scene.meshes[m];
      const size_t prim = t - first_of[m];
      soup.mesh[t] = static_cast<uint32_t>(m);
      soup.prim[t] = static_cast<uint32_t>(prim);
      soup.opaque[t] = mesh_opaque[m];
      for (int c = 0; c < 3; ++c) {
        const Vec3 q = space.to_light(mesh.vertex(prim, c));
        soup.x[c][t] = q.x, soup.y[c][t] = q.y, soup.z[c][t] = q.z;
      }
    }
  });
}

}  // namespace

LightSetup setup_light_space(const ShadowContext& ctx) {
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  LightSetup setup;
  setup.active =
      parallel_indices(g.pixel_count(), [&](size_t i) { return ctx.receivers[i] == kActive; });
  setup.back_facing = static_cast<uint64_t>(
      std::count(ctx.receivers.pixels().begin(), ctx.receivers.pixels().end(), kBackFacing));
  setup.frame0 = light_frame(light, light.center + Vec3(0.0f, -1.0f, 0.0f));
  setup.toward = setup.frame0.emit_normal;
  if (light.shape == LightShape::point || light.shape == LightShape::sphere) {
    // No emitting plane: the light space faces the receivers.
    Bounds3 b;
    for (uint32_t i : setup.active) b.extend(g.shadow_origin(i));
    setup.toward = b.empty() ? Vec3(0.0f, -1.0f, 0.0f) : b.center() - light.center;
  }
  setup.space = make_light_space(light, setup.frame0, setup.toward, +1);
  setup.p_light.resize(setup.active.size());
  parallel_chunks(setup.active.size(), 4096, [&](size_t b, size_t e) {
    for (size_t a = b; a < e; ++a)
      setup.p_light[a] = setup.space.to_light(g.shadow_origin(setup.active[a]));
  });
  fill_soup(ctx.scene, setup.space, setup);
  return setup;
}

SharedSamples shared_samples(const ShadowContext& ctx, const LightSetup& setup) {
  const Light& light = ctx.light;
  const int n = ctx.samples.count();
  const bool per_pixel = ctx.samples.per_pixel();
  SharedSamples out;
  if (light.shape == LightShape::point) {
    out.corners = {Vec3(0.0f)};
  } else {
    const bool sphere = light.shape == LightShape::sphere;
    const float r = sphere ? light.radius / glm::length(setup.space.axis_n) : 0.0f;  // z units
    out.light_max_z = r;
    for (float z : sphere ? std::vector<float>{-r, r} : std::vector<float>{0.0f})
      for (int c = 0; c < 4; ++c)
        out.corners.emplace_back(static_cast<float>(c & 1), static_cast<float>(c >> 1), z);
  }
  out.uv.resize(n);
  out.emit_words.assign((n + 63) / 64, 0);
  if (per_pixel) return out;  // uv unused; the box is the unit square
  ctx.samples.pixel_samples(0, 0, out.uv);
  out.uv_lo = Vec2(kInfinity), out.uv_hi = Vec2(-kInfinity);
  out.u.resize(n), out.v.resize(n);
  for (int s = 0; s < n; ++s) {
    const Vec2& q = out.uv[s];
    out.uv_lo = glm::min(out.uv_lo, q), out.uv_hi = glm::max(out.uv_hi, q);
    out.u[s] = q.x, out.v[s] = q.y;
    if (setup.frame0.emits(q)) out.emit_words[s >> 6] |= uint64_t{1} << (s & 63), ++out.emit_count;
  }
  return out;
}

std::vector<uint8_t> box_cull_pixels(const ShadowContext& ctx, const LightSetup& setup,
                                     const SharedSamples& samples, bool enabled) {
  constexpr size_t kMaxCullBoxes = 256;
  std::vector<uint8_t> may_be_shadowed(setup.active.size(), 1);
  const LightShape shape = ctx.light.shape;
  if (!enabled || ctx.samples.per_pixel() || shape == LightShape::point ||
      shape == LightShape::sphere)
    return may_be_shadowed;
  FlatLight light_box;
  light_box.flat = true;
  light_box.lx0 = samples.uv_lo.x, light_box.lx1 = samples.uv_hi.x;
  light_box.ly0 = samples.uv_lo.y, light_box.ly1 = samples.uv_hi.y;
  std::vector<PackedTriangle> boxes;
  for (const Mesh& mesh : ctx.scene.meshes) {
    if (!mesh.casts_shadows || mesh.triangle_count() == 0) continue;
    const Bounds3 world = mesh.bounds();
    Vec3 lo(kInfinity), hi(-kInfinity);
    for (int c = 0; c < 8; ++c) {
      const Vec3 q = setup.space.to_light(Vec3(c & 1 ? world.hi.x : world.lo.x,
                                               c & 2 ? world.hi.y : world.lo.y,
                                               c & 4 ? world.hi.z : world.lo.z));
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    boxes.push_back(box_cull_bounds(light_box, lo, hi));
  }
  if (boxes.size() > kMaxCullBoxes) return may_be_shadowed;
  parallel_chunks(setup.active.size(), 4096, [&](size_t b, size_t e) {
    for (size_t a = b; a < e; ++a) {
      const Vec3& q = setup.p_light[a];
      const ItemBounds own = item_bounds(light_box, &q.x, &q.y, &q.z, 1);
      bool any = !(q.z > 0.0f);
      for (size_t i = 0; i < boxes.size() && !any; ++i) any = may_block(boxes[i], own);
      may_be_shadowed[a] = any;
    }
  });
  return may_be_shadowed;
}

}  // namespace penumbra::gears
