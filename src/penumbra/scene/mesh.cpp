#include "penumbra/scene/mesh.hpp"

#include <algorithm>

namespace penumbra {

Bounds3 Mesh::bounds() const {
  Bounds3 b;
  for (const Vec3& p : positions) b.extend(p);
  return b;
}

void transform_mesh(Mesh& mesh, const Mat4& m) {
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(m)));
  for (Vec3& p : mesh.positions) p = Vec3(m * Vec4(p, 1.0f));
  for (Vec3& n : mesh.normals) {
    const Vec3 t = normal_matrix * n;
    const float len = glm::length(t);
    n = len > 0.0f ? t / len : n;
  }
  if (glm::determinant(glm::mat3(m)) < 0.0f) {  // a mirror: keep triangles facing outward
    for (Triangle& t : mesh.triangles) std::swap(t.v[1], t.v[2]);
  }
}

bool is_degenerate(const Mesh& mesh, const Triangle& t) {
  constexpr double kDegenerateRelative = 1e-10;
  const DVec3 a(mesh.positions[t.v[0]]), b(mesh.positions[t.v[1]]), c(mesh.positions[t.v[2]]);
  const DVec3 e1 = b - a, e2 = c - a, e3 = c - b;
  const double longest2 = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
  const double twice_area = glm::length(glm::cross(e1, e2));
  return !(twice_area > kDegenerateRelative * longest2);
}

}  // namespace penumbra
