#include "penumbra/gpu/gears_vk_host.hpp"

#include <algorithm>
#include <bit>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/material.hpp"
#include "penumbra/shadows/gears/lut.hpp"
#include "penumbra/shadows/light_weights.hpp"

namespace penumbra::gpu::gears_host {

namespace {

void push4(std::vector<float>& out, const Vec3& v) {
  out.insert(out.end(), {v.x, v.y, v.z, 0.0f});
}

/// A triangle's slab bounds (hx0, hx1, hy0, hy1) of [Wang 2014 §4.2]'s per-item cull, as
/// gears::pack_triangles computes them (gears/item_cull.hpp): a pixel whose own bounds miss them
/// cannot be blocked by it. `v`: 3 light-space vertices, stride 4; `sgn`: the side's mirror.
Vec4 slab_bounds(const float* v, float zmin, float sgn, const gears::FlatLight& light) {
  constexpr float kRel = 1e-4f, kAbs = 1e-6f;  // item_cull.cpp's widening
  if (!light.flat || !(zmin > 0.0f)) return Vec4(kInfinity, -kInfinity, kInfinity, -kInfinity);
  float hx0 = -kInfinity, hx1 = kInfinity, hy0 = -kInfinity, hy1 = kInfinity;
  for (int c = 0; c < 3; ++c) {
    const float x = v[4 * c], y = v[4 * c + 1], z = sgn * v[4 * c + 2];
    hx0 = std::max(hx0, (x - light.lx0) / z), hx1 = std::min(hx1, (x - light.lx1) / z);
    hy0 = std::max(hy0, (y - light.ly0) / z), hy1 = std::min(hy1, (y - light.ly1) / z);
  }
  return Vec4(hx0 + kRel * std::abs(hx0) + kAbs, hx1 - kRel * std::abs(hx1) - kAbs,
              hy0 + kRel * std::abs(hy0) + kAbs, hy1 - kRel * std::abs(hy1) - kAbs);
}

/// The occluders in order of this side's nearest depth (z mirrored by `side`), ties by id: the
/// CPU's order [Wang 2014 §4.2, the prefix sum in triangle order], so each cell's list, a stable
/// sort by cell of the pairs, is in depth order and a pixel's depth cut is a prefix of it. Each
/// triangle also gets its slab bounds for the per-pixel cull (gears::pack_triangles, `flat`: this
/// side's light).
SideTriangles sort_by_depth(const std::vector<float>& tris, const std::vector<float>& alpha,
                            int side, const gears::FlatLight& flat,
                            const gears::TrianglePlane* planes, const uint32_t* solid) {
  const size_t count = tris.size() / 12;
  const float sgn = static_cast<float>(side);
  std::vector<float> zmin(count);
  for (size_t t = 0; t < count; ++t)
    zmin[t] =
        std::min(sgn * tris[12 * t + 2], std::min(sgn * tris[12 * t + 6], sgn * tris[12 * t + 10]));
  std::vector<uint32_t> order(count);
  for (size_t t = 0; t < count; ++t) order[t] = static_cast<uint32_t>(t);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return zmin[a] < zmin[b]; });
  SideTriangles out;
  out.tris.resize(tris.size());
  out.alpha.resize(count * kTriInfo);
  for (size_t r = 0; r < count; ++r) {
    const size_t t = order[r];
    std::copy_n(tris.begin() + 12 * t, 12, out.tris.begin() + 12 * r);
    float* info = &out.alpha[kTriInfo * r];
    std::copy_n(alpha.begin() + 12 * t, 12, info);
    out.tris[12 * r + 3] = zmin[t];
    const Vec4 slab = slab_bounds(&tris[12 * t], zmin[t], sgn, flat);
    for (int i = 0; i < 4; ++i) info[12 + i] = slab[i];
    // No plane data: a plane no sample is strictly on either side of.
    const gears::TrianglePlane pl =
        planes ? planes[t] : gears::TrianglePlane{0, 0, 0, 0, 0, -kInfinity, kInfinity, 0};
    const float plane[8] = {
        pl.nx, pl.ny,   pl.nz,   pl.d,
        pl.n1, pl.lmin, pl.lmax, std::bit_cast<float>(solid ? solid[t] : gears::kNoSolid)};
    std::copy_n(plane, 8, info + 16);
  }
  return out;
}

}  // namespace

Occluders gather_occluders(const Scene& scene, const gears::LightSpace& space) {
  Occluders o;
  std::vector<int> texel_offset(scene.textures.size(), -1);
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.casts_shadows) continue;
    const Material& mat = scene.material_of(mesh);
    o.semi_opaque |= mat.transmittance > 0.0f;
    o.translucent |= mat.transmittance > 0.0f || mat.alpha_texture >= 0;
    const Texture* tex = mat.alpha_texture >= 0 ? &scene.textures[mat.alpha_texture] : nullptr;
    float header[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    if (tex) {
      int& offset = texel_offset[mat.alpha_texture];
      if (offset < 0) {
        offset = static_cast<int>(o.texels.size());
        for (int y = 0; y < tex->height; ++y)
          for (int x = 0; x < tex->width; ++x)
            o.texels.push_back(tex->channel(x, y, 0) >= kAlphaCutoff ? 1u : 0u);
      }
      header[0] = std::bit_cast<float>(static_cast<uint32_t>(offset));
      header[1] = static_cast<float>(tex->width), header[2] = static_cast<float>(tex->height);
      header[3] = 1.0f;
    }
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      for (int c = 0; c < 3; ++c) push4(o.tris, space.to_light(mesh.vertex(t, c)));
      o.mesh.push_back(static_cast<uint32_t>(&mesh - scene.meshes.data()));
      o.prim.push_back(static_cast<uint32_t>(t));
      o.opaque.push_back(mat.is_opaque() ? 1 : 0);
      o.alpha.insert(o.alpha.end(), header, header + 4);
      Vec2 uv[3] = {Vec2(0.0f), Vec2(0.0f), Vec2(0.0f)};
      if (tex && !mesh.uvs.empty())
        for (int c = 0; c < 3; ++c) uv[c] = mesh.uvs[mesh.triangles[t].v[c]];
      o.alpha.insert(o.alpha.end(), {uv[0].x, uv[0].y, uv[1].x, uv[1].y, uv[2].x, uv[2].y,
                                     mat.transmittance, 0.0f});
    }
  }
  return o;
}

gears::TriangleSoup soup_of(const Occluders& o) {
  gears::TriangleSoup soup;
  soup.resize(o.mesh.size());
  for (size_t t = 0; t < o.mesh.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      soup.x[c][t] = o.tris[12 * t + 4 * c];
      soup.y[c][t] = o.tris[12 * t + 4 * c + 1];
      soup.z[c][t] = o.tris[12 * t + 4 * c + 2];
    }
    soup.mesh[t] = o.mesh[t], soup.prim[t] = o.prim[t], soup.opaque[t] = o.opaque[t];
  }
  return soup;
}

SideTriangles side_cull_data(const gears::GridCamera& cam, int side, bool shrink, Vec2 uv_lo,
                             Vec2 uv_hi, const std::vector<Vec3>& p_light, std::vector<float>& pix,
                             const Occluders& occ, const gears::TriangleSoup* soup,
                             const gears::Solids& solids) {
  gears::FlatLight flat = gears::flat_light(cam);
  if (shrink) flat = gears::shrink_to_samples(flat, uv_lo, uv_hi);
  for (size_t a = 0; a < p_light.size(); ++a) {
    const Vec3& q = p_light[a];
    if ((side > 0) != (q.z >= 0.0f)) continue;
    const float z = static_cast<float>(side) * q.z;
    const gears::ItemBounds b = gears::item_bounds(flat, &q.x, &q.y, &z, 1);
    float* out = &pix[20 * a + 16];
    out[0] = b.ix0, out[1] = b.ix1, out[2] = b.iy0, out[3] = b.iy1;
  }
  const UninitVector<gears::TrianglePlane> planes =
      soup ? gears::triangle_planes(*soup, gears::plane_test_corners(flat, cam))
           : UninitVector<gears::TrianglePlane>{};
  return sort_by_depth(occ.tris, occ.alpha, side, flat, soup ? planes.data() : nullptr,
                       solids.count() > 0 ? solids.of_triangle.data() : nullptr);
}

Plan plan_of(const ShadowContext& ctx, bool lut) {
  Plan p;
  const Light& light = ctx.light;
  p.n = ctx.samples.count();
  p.k = ctx.samples.k();
  if (p.k > 64) throw Error("gears on vulkan: at most 64×64 light samples (--samples ≤ 64)");
  p.sphere = light.shape == LightShape::sphere;
  p.point = light.shape == LightShape::point;
  p.per_pixel = ctx.samples.per_pixel();
  p.use_lut = lut && !p.per_pixel && !p.point;
  p.use_rows = ctx.samples.spec().pattern == SamplePattern::grid && !p.per_pixel && p.k <= 32 &&
               !p.point && !p.use_lut;
  p.ns = p.point ? 1 : p.n;
  p.words = static_cast<uint32_t>((p.ns + 31) / 32);
  p.emission = light.is_textured() ? &ctx.scene.textures[light.emission_texture] : nullptr;
  return p;
}

void pixel_data(const ShadowContext& ctx, const gears::LightSpace& space, const Plan& plan,
                const std::vector<uint32_t>& active, std::vector<Vec3>& p_light,
                std::vector<float>& pix) {
  const GBuffer& g = ctx.gbuffer;
  p_light.resize(active.size());
  pix.clear();
  pix.reserve(active.size() * 20);
  for (size_t a = 0; a < active.size(); ++a) {
    const Vec3 p = space.to_light(g.shadow_origin(active[a]));
    p_light[a] = p;
    Vec3 w = -p, eu(1.0f, 0.0f, 0.0f), ev(0.0f, 1.0f, 0.0f);
    if (plan.point) {
      eu = ev = Vec3(0.0f);
    } else if (plan.sphere) {
      // The sphere's silhouette disk as seen from this pixel (scene/light.hpp).
      const LightFrame f = light_frame(ctx.light, g.shadow_origin(active[a]));
      auto dir = [&](const Vec3& d) {
        return Vec3(glm::dot(space.inv_u, d), glm::dot(space.inv_v, d), glm::dot(space.inv_n, d));
      };
      w = space.to_light(f.corner) - p;
      eu = dir(f.edge_u);
      ev = dir(f.edge_v);
    }
    push4(pix, p), push4(pix, w), push4(pix, eu), push4(pix, ev);
    push4(pix, Vec3(0.0f));  // the pixel's slab bounds, set per side
  }
}

SampleSetup sample_setup(const ShadowContext& ctx, const Plan& plan, const LightFrame& frame0,
                         const std::vector<uint32_t>& active, int words64) {
  const GBuffer& g = ctx.gbuffer;
  const int n = plan.n, k = plan.k;
  SampleSetup out;
  out.shared.resize(n);
  ctx.samples.pixel_samples(0, 0, out.shared);
  if (!plan.per_pixel) {
    out.uv_lo = Vec2(kInfinity), out.uv_hi = Vec2(-kInfinity);
    for (const Vec2& s : out.shared)
      out.uv_lo = glm::min(out.uv_lo, s), out.uv_hi = glm::max(out.uv_hi, s);
  }
  if (plan.point) out.uv_lo = out.uv_hi = Vec2(0.0f);
  out.emit_rows.assign(k, 0);
  out.emit_words.assign(words64, 0);
  for (int s = 0; s < n; ++s)
    if (frame0.emits(out.shared[s])) {
      if (plan.use_rows) out.emit_rows[s / k] |= 1u << (s % k);
      out.emit_words[s >> 6] |= uint64_t{1} << (s & 63);
      ++out.emit_count;
    }
  if (plan.use_rows) {
    for (const Vec2& s : out.shared) out.sample_uv.insert(out.sample_uv.end(), {s.x, s.y});
    return out;
  }
  const bool own = plan.per_pixel || plan.point;
  std::vector<Vec2> uvs(n);
  for (size_t a = 0; a < (own ? active.size() : 1); ++a) {
    const uint32_t pixel = own ? active[a] : 0;
    if (plan.per_pixel)
      ctx.samples.pixel_samples(static_cast<int>(pixel % g.width),
                                static_cast<int>(pixel / g.width), uvs);
    else
      uvs = out.shared;
    const LightFrame frame = plan.sphere ? light_frame(ctx.light, g.shadow_origin(pixel)) : frame0;
    std::vector<uint32_t> bits(plan.words, 0);
    for (int s = 0; s < plan.ns; ++s) {
      out.sample_uv.insert(out.sample_uv.end(),
                           {plan.point ? 0.0f : uvs[s].x, plan.point ? 0.0f : uvs[s].y});
      const bool emits = plan.point || (own ? frame.emits(uvs[s]) : frame0.emits(uvs[s]));
      if (emits) bits[s >> 5] |= 1u << (s & 31);
    }
    out.emit_bits.insert(out.emit_bits.end(), bits.begin(), bits.end());
  }
  return out;
}

void append_lut(std::span<const Vec2> shared, int resolution, std::vector<uint32_t>& texels) {
  const gears::EdgeLut lut(shared, resolution, resolution);
  texels[0] = static_cast<uint32_t>(texels.size());
  texels[1] = static_cast<uint32_t>(lut.angles());
  texels[2] = static_cast<uint32_t>(lut.offsets());
  texels[3] = std::bit_cast<uint32_t>(lut.radius());
  for (uint64_t w : lut.table())
    texels.insert(texels.end(), {static_cast<uint32_t>(w), static_cast<uint32_t>(w >> 32)});
}

void read_back(const ShadowContext& ctx, const Plan& plan, const SampleSetup& ss,
               const std::vector<uint32_t>& active, const std::vector<uint32_t>& rows,
               size_t mask_words, bool semi_opaque, SampleMasks& masks, Visibility& vis) {
  const GBuffer& g = ctx.gbuffer;
  const int n = plan.n, k = plan.k;
  std::vector<Vec2> uvs(n);
  std::vector<float> sample_vis(n);
  for (size_t a = 0; a < active.size(); ++a) {
    const uint32_t pixel = active[a];
    uint64_t* m = masks.pixel(pixel);
    if (plan.use_rows) {  // row j holds samples j·k … j·k + k − 1
      for (int j = 0; j < k; ++j) {
        const uint64_t bits = rows[a * k + j];
        const int p = j * k;
        m[p >> 6] |= bits << (p & 63);
        if ((p & 63) + k > 64) m[(p >> 6) + 1] |= bits >> (64 - (p & 63));
      }
    } else if (plan.point) {  // the light's one sample stands for all of them
      if (rows[a] & 1u)
        for (int s = 0; s < n; ++s) m[s >> 6] |= uint64_t{1} << (s & 63);
    } else {
      for (uint32_t w = 0; w < plan.words; ++w)
        m[w >> 1] |= uint64_t{rows[a * plan.words + w]} << (32 * (w & 1));
    }
    if (!plan.emission && !plan.per_pixel && !plan.point && !semi_opaque) {
      int blocked = 0;
      for (int i = 0; i < masks.words_per_pixel(); ++i)
        blocked += std::popcount(m[i] & ss.emit_words[i]);
      SampleWeights w;
      w.visible = Vec3(static_cast<float>(ss.emit_count - blocked));
      w.total = Vec3(static_cast<float>(ss.emit_count));
      vis.lit[pixel] = w.visible_fraction();
      continue;
    }
    const LightFrame frame = light_frame(ctx.light, g.shadow_origin(pixel));
    ctx.samples.pixel_samples(static_cast<int>(pixel % g.width), static_cast<int>(pixel / g.width),
                              uvs);
    // Unblocked samples: the product of the semi-opaque layers they cross (a point light's one
    // sample standing for all), as the CPU shades them.
    const uint32_t* trans = semi_opaque ? rows.data() + mask_words + a * plan.ns : nullptr;
    for (int s = 0; s < n; ++s)
      sample_vis[s] = masks.blocked(pixel, s)
                          ? 0.0f
                          : (trans ? std::bit_cast<float>(trans[plan.point ? 0 : s]) : 1.0f);
    const SampleWeights w =
        accumulate_sample_weights(frame, plan.emission, ctx.light.radiance, uvs, sample_vis);
    vis.lit[pixel] = w.visible_fraction();
    if (plan.emission) vis.lit_rgb->operator[](pixel) = w.visible_fraction_rgb();
  }
}

std::vector<Vec3> light_corners(const Plan& plan, float r) {
  if (plan.point) return {Vec3(0.0f)};
  std::vector<Vec3> corners;
  for (float z : plan.sphere ? std::vector<float>{-r, r} : std::vector<float>{0.0f})
    for (int c = 0; c < 4; ++c)
      corners.emplace_back(static_cast<float>(c & 1), static_cast<float>(c >> 1), z);
  return corners;
}

void active_pixels_and_toward(const ShadowContext& ctx, const Plan& plan, HostFrame& h) {
  const GBuffer& g = ctx.gbuffer;
  const Light& light = ctx.light;
  for (size_t i = 0; i < g.pixel_count(); ++i)
    if (ctx.receivers[i] == kActive) h.active.push_back(static_cast<uint32_t>(i));
  h.frame0 = light_frame(light, light.center + Vec3(0.0f, -1.0f, 0.0f));
  h.toward = h.frame0.emit_normal;
  if (plan.sphere || plan.point) {
    Bounds3 b;
    for (uint32_t i : h.active) b.extend(g.shadow_origin(i));
    h.toward = b.empty() ? Vec3(0.0f, -1.0f, 0.0f) : b.center() - light.center;
  }
}

void mark_outside_solids(HostFrame& h) {
  for (size_t a = 0; a < h.active.size(); ++a) {
    const uint64_t outside = h.solids.outside(h.p_light[a]);
    h.pix[20 * a + 7] = std::bit_cast<float>(static_cast<uint32_t>(outside));
    h.pix[20 * a + 11] = std::bit_cast<float>(static_cast<uint32_t>(outside >> 32));
  }
}

}  // namespace penumbra::gpu::gears_host
