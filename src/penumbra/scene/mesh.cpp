#include "penumbra/scene/mesh.hpp"

namespace penumbra {

Bounds3 Mesh::bounds() const {
  Bounds3 b;
  for (const Vec3& p : positions) b.extend(p);
  return b;
}

Vec2 Mesh::uv_at(size_t tri, float u, float v) const {
  if (uvs.empty()) return Vec2(0.0f);
  const Triangle& t = triangles[tri];
  return (1.0f - u - v) * uvs[t.v[0]] + u * uvs[t.v[1]] + v * uvs[t.v[2]];
}

}  // namespace penumbra
