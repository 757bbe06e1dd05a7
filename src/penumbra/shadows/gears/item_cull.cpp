#include "penumbra/shadows/gears/item_cull.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/core/parallel.hpp"
#include "penumbra/shadows/gears/solids.hpp"

namespace penumbra::gears {

namespace {

// The bounds are widened by this relative amount (and a tiny absolute one): the rasterizer's own
// rounding is ~10⁻⁶ relative, so a triangle it would find covering a sample is never culled.
constexpr float kRel = 1e-4f, kAbs = 1e-6f;

float widen_up(float x) {
  return x + kRel * std::abs(x) + kAbs;
}
float widen_down(float x) {
  return x - kRel * std::abs(x) - kAbs;
}

}  // namespace

FlatLight flat_light(const GridCamera& camera) {
  FlatLight f;
  f.max_z = camera.light_max_z;
  if (camera.light_min_z != 0.0f || camera.light_max_z != 0.0f) return f;  // sphere: not flat
  f.flat = true;
  f.lx0 = f.ly0 = kInfinity;
  f.lx1 = f.ly1 = -kInfinity;
  for (const Vec3& c : camera.light_corners) {
    if (c.z != 0.0f) return FlatLight{.max_z = camera.light_max_z};
    f.lx0 = std::min(f.lx0, c.x), f.lx1 = std::max(f.lx1, c.x);
    f.ly0 = std::min(f.ly0, c.y), f.ly1 = std::max(f.ly1, c.y);
  }
  return f;
}

FlatLight shrink_to_samples(FlatLight light, Vec2 lo, Vec2 hi) {
  if (!light.flat || !(lo.x <= hi.x && lo.y <= hi.y)) return light;
  light.lx0 = std::max(light.lx0, lo.x), light.lx1 = std::min(light.lx1, hi.x);
  light.ly0 = std::max(light.ly0, lo.y), light.ly1 = std::min(light.ly1, hi.y);
  return light;
}

UninitVector<PackedTriangle> pack_triangles(const TriangleSoup& soup, int side,
                                            const std::vector<float>& zmin,
                                            const FlatLight& light) {
  UninitVector<PackedTriangle> out(soup.size());  // every field written below
  const float sgn = side < 0 ? -1.0f : 1.0f;
  parallel_chunks(soup.size(), 4096, [&](size_t b, size_t e) {
    for (size_t t = b; t < e; ++t) {
      PackedTriangle& p = out[t];
      for (int c = 0; c < 3; ++c) {
        p.v[3 * c + 0] = soup.x[c][t];
        p.v[3 * c + 1] = soup.y[c][t];
        p.v[3 * c + 2] = soup.z[c][t];
      }
      p.zmin = zmin[t];
      p.hx0 = p.hy0 = kInfinity;
      p.hx1 = p.hy1 = -kInfinity;
      p.opaque = soup.opaque[t];
      p.solid = kNoSolid;
      if (!light.flat || !(zmin[t] > 0.0f)) continue;  // reaches the light plane: keep
      float hx0 = -kInfinity, hx1 = kInfinity, hy0 = -kInfinity, hy1 = kInfinity;
      for (int c = 0; c < 3; ++c) {
        const float x = soup.x[c][t], y = soup.y[c][t], z = sgn * soup.z[c][t];
        hx0 = std::max(hx0, (x - light.lx0) / z), hx1 = std::min(hx1, (x - light.lx1) / z);
        hy0 = std::max(hy0, (y - light.ly0) / z), hy1 = std::min(hy1, (y - light.ly1) / z);
      }
      p.hx0 = widen_up(hx0), p.hx1 = widen_down(hx1);
      p.hy0 = widen_up(hy0), p.hy1 = widen_down(hy1);
    }
  });
  return out;
}

PackedTriangle box_cull_bounds(const FlatLight& light, Vec3 lo, Vec3 hi) {
  PackedTriangle p{};
  p.solid = kNoSolid;
  const Vec3 margin = 1e-4f * (hi - lo) + 1e-4f * glm::max(glm::abs(lo), glm::abs(hi)) + kAbs;
  lo -= margin, hi += margin;
  p.zmin = lo.z;
  p.hx0 = p.hy0 = kInfinity;
  p.hx1 = p.hy1 = -kInfinity;
  if (!light.flat || !(lo.z > 0.0f)) return p;
  float hx0 = -kInfinity, hx1 = kInfinity, hy0 = -kInfinity, hy1 = kInfinity;
  for (int c = 0; c < 8; ++c) {
    // (x − lx0)/z over the box is extremal at a corner (a linear-fractional function, z > 0).
    const float x = c & 1 ? hi.x : lo.x, y = c & 2 ? hi.y : lo.y, z = c & 4 ? hi.z : lo.z;
    hx0 = std::max(hx0, (x - light.lx0) / z), hx1 = std::min(hx1, (x - light.lx1) / z);
    hy0 = std::max(hy0, (y - light.ly0) / z), hy1 = std::min(hy1, (y - light.ly1) / z);
  }
  p.hx0 = widen_up(hx0), p.hx1 = widen_down(hx1);
  p.hy0 = widen_up(hy0), p.hy1 = widen_down(hy1);
  return p;
}

ItemBounds item_bounds(const FlatLight& light, const float* x, const float* y, const float* z,
                       int count) {
  ItemBounds b{light.max_z, kInfinity, -kInfinity, kInfinity, -kInfinity};
  bool on_light_plane = false;
  for (int i = 0; i < count; ++i) {
    b.zmax = std::max(b.zmax, z[i]);
    on_light_plane |= !(z[i] > 0.0f);
    if (!light.flat || on_light_plane) continue;
    b.ix0 = std::min(b.ix0, (x[i] - light.lx0) / z[i]);
    b.ix1 = std::max(b.ix1, (x[i] - light.lx1) / z[i]);
    b.iy0 = std::min(b.iy0, (y[i] - light.ly0) / z[i]);
    b.iy1 = std::max(b.iy1, (y[i] - light.ly1) / z[i]);
  }
  if (!light.flat || on_light_plane) b.ix0 = b.iy0 = -kInfinity, b.ix1 = b.iy1 = kInfinity;
  return b;
}

void group_samples(const FlatLight& light, const float* x, const float* y, const float* z,
                   int count, int group_size, std::vector<int>& order, std::vector<int>& ends) {
  order.resize(count);
  for (int i = 0; i < count; ++i) order[i] = i;
  ends.clear();
  bool slabs = light.flat && group_size > 0;
  for (int i = 0; i < count && slabs; ++i) slabs = z[i] > 0.0f;
  if (!slabs || count <= group_size) {
    ends.push_back(count);
    return;
  }
  // The slab coordinates, once per sample (the splits compare them many times).
  thread_local std::vector<float> keys;
  keys.resize(2 * static_cast<size_t>(count));
  for (int i = 0; i < count; ++i)
    keys[2 * i] = (x[i] - light.lx0) / z[i], keys[2 * i + 1] = (y[i] - light.ly0) / z[i];
  auto key = [&](int i, int axis) { return keys[2 * i + axis]; };
  // Depth-first over [begin, end) ranges of `order`, so the groups come out in order.
  struct Range {
    int begin, end;
  };
  Range stack[64];
  int top = 0;
  stack[top++] = {0, count};
  while (top > 0) {
    const Range r = stack[--top];
    if (r.end - r.begin <= group_size) {
      ends.push_back(r.end);
      continue;
    }
    float lo[2] = {kInfinity, kInfinity}, hi[2] = {-kInfinity, -kInfinity};
    for (int j = r.begin; j < r.end; ++j)
      for (int axis = 0; axis < 2; ++axis)
        lo[axis] = std::min(lo[axis], key(order[j], axis)),
        hi[axis] = std::max(hi[axis], key(order[j], axis));
    const int axis = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1;
    const int mid = r.begin + (r.end - r.begin) / 2;
    std::nth_element(order.begin() + r.begin, order.begin() + mid, order.begin() + r.end,
                     [&](int a, int b) { return key(a, axis) < key(b, axis); });
    stack[top++] = {mid, r.end};  // popped second
    stack[top++] = {r.begin, mid};
  }
}

std::vector<Vec3> plane_test_corners(const FlatLight& light, const GridCamera& camera) {
  if (!light.flat) return camera.light_corners;
  return {Vec3(light.lx0, light.ly0, 0.0f), Vec3(light.lx1, light.ly0, 0.0f),
          Vec3(light.lx0, light.ly1, 0.0f), Vec3(light.lx1, light.ly1, 0.0f)};
}

UninitVector<TrianglePlane> triangle_planes(const TriangleSoup& soup,
                                            const std::vector<Vec3>& light_corners) {
  UninitVector<TrianglePlane> out(soup.size());  // every field written below
  float corner_inf = 0.0f;
  for (const Vec3& c : light_corners)
    corner_inf = std::max({corner_inf, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
  parallel_chunks(soup.size(), 4096, [&](size_t b, size_t e) {
    for (size_t t = b; t < e; ++t) {
      DVec3 v[3];
      for (int c = 0; c < 3; ++c) v[c] = DVec3(soup.x[c][t], soup.y[c][t], soup.z[c][t]);
      const DVec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
      TrianglePlane& p = out[t];
      p.nx = static_cast<float>(n.x), p.ny = static_cast<float>(n.y),
      p.nz = static_cast<float>(n.z);
      // d for the rounded normal, so n·q − d is the signed distance to one plane through A.
      p.d =
          static_cast<float>(double(p.nx) * v[0].x + double(p.ny) * v[0].y + double(p.nz) * v[0].z);
      p.n1 = std::abs(p.nx) + std::abs(p.ny) + std::abs(p.nz);
      p.pad = 0.0f;
      double lo = 1e300, hi = -1e300;
      for (const Vec3& c : light_corners) {
        const double s = double(p.nx) * c.x + double(p.ny) * c.y + double(p.nz) * c.z - p.d;
        lo = std::min(lo, s), hi = std::max(hi, s);
      }
      const double tol = 2.0 * kPlaneRel * (p.n1 * corner_inf + std::abs(p.d));
      p.lmin = static_cast<float>(lo - tol);
      p.lmax = static_cast<float>(hi + tol);
      if (!(n.x != 0.0 || n.y != 0.0 || n.z != 0.0)) p.lmin = -kInfinity, p.lmax = kInfinity;
    }
  });
  return out;
}

}  // namespace penumbra::gears
