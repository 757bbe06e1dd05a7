#include "penumbra/scene/shapes.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra {

Mesh make_quad(const Vec3& center, const Vec3& edge_u, const Vec3& edge_v) {
  Mesh m;
  m.name = "quad";
  const Vec3 c0 = center - 0.5f * (edge_u + edge_v);
  m.positions = {c0, c0 + edge_u, c0 + edge_u + edge_v, c0 + edge_v};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  return m;
}

Mesh make_box(const Vec3& center, const Vec3& h) {
  Mesh m;
  m.name = "box";
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(center +
                          Vec3((i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z));
  // Outward-facing (counter-clockwise seen from outside) faces.
  const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.push_back({{f[0], f[1], f[2]}});
    m.triangles.push_back({{f[0], f[2], f[3]}});
  }
  return m;
}

Mesh make_sphere(const Vec3& center, float radius, int rings, int segments) {
  rings = std::max(rings, 2);  // fewer bands cannot close the surface
  segments = std::max(segments, 3);
  Mesh m;
  m.name = "sphere";
  const float pi = static_cast<float>(kPi);
  m.positions.push_back(center + Vec3(0, radius, 0));
  m.normals.push_back(Vec3(0, 1, 0));
  for (int r = 1; r < rings; ++r) {
    const float theta = pi * static_cast<float>(r) / static_cast<float>(rings);
    for (int s = 0; s < segments; ++s) {
      const float phi = 2.0f * pi * static_cast<float>(s) / static_cast<float>(segments);
      const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      m.positions.push_back(center + radius * n);
      m.normals.push_back(n);
    }
  }
  m.positions.push_back(center - Vec3(0, radius, 0));
  m.normals.push_back(Vec3(0, -1, 0));
  const auto ring_vertex = [&](int r, int s) {
    return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments));
  };
  const uint32_t south = static_cast<uint32_t>(m.positions.size() - 1);
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({{0, ring_vertex(1, s + 1), ring_vertex(1, s)}});
    for (int r = 1; r < rings - 1; ++r) {
      const uint32_t a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
      const uint32_t c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
      m.triangles.push_back({{a, b, d}});
      m.triangles.push_back({{a, d, c}});
    }
    m.triangles.push_back({{south, ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1)}});
  }
  return m;
}

Mesh make_torus(const Vec3& center, float major_radius, float minor_radius, int major_segments,
                int minor_segments) {
  major_segments = std::max(major_segments, 3);
  minor_segments = std::max(minor_segments, 3);
  Mesh m;
  m.name = "torus";
  const float pi = static_cast<float>(kPi);
  for (int i = 0; i < major_segments; ++i) {
    const float phi = 2.0f * pi * static_cast<float>(i) / static_cast<float>(major_segments);
    const Vec3 radial(std::cos(phi), 0.0f, std::sin(phi));
    for (int j = 0; j < minor_segments; ++j) {
      const float theta = 2.0f * pi * static_cast<float>(j) / static_cast<float>(minor_segments);
      const Vec3 n = std::cos(theta) * radial + Vec3(0.0f, std::sin(theta), 0.0f);
      m.positions.push_back(center + major_radius * radial + minor_radius * n);
      m.normals.push_back(n);
    }
  }
  const auto vertex = [&](int i, int j) {
    return static_cast<uint32_t>((i % major_segments) * minor_segments + (j % minor_segments));
  };
  // Outward facing: (a, b, d) turns counter-clockwise seen from outside the tube.
  for (int i = 0; i < major_segments; ++i) {
    for (int j = 0; j < minor_segments; ++j) {
      const uint32_t a = vertex(i, j), b = vertex(i, j + 1);
      const uint32_t c = vertex(i + 1, j), d = vertex(i + 1, j + 1);
      m.triangles.push_back({{a, b, d}});
      m.triangles.push_back({{a, d, c}});
    }
  }
  return m;
}

Mesh make_open_prism(const Vec3& a, const Vec3& b, float radius, float phase) {
  Mesh m;
  m.name = "prism";
  Vec3 t, s;
  orthonormal_basis(glm::normalize(b - a), t, s);
  for (int k = 0; k < 3; ++k) {
    const float angle = phase + 2.0f * static_cast<float>(kPi) * static_cast<float>(k) / 3.0f;
    const Vec3 offset = radius * (std::cos(angle) * t + std::sin(angle) * s);
    m.positions.push_back(a + offset);
    m.positions.push_back(b + offset);
  }
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t a0 = 2 * k, b0 = 2 * k + 1, a1 = 2 * ((k + 1) % 3), b1 = a1 + 1;
    m.triangles.push_back({{a0, a1, b1}});
    m.triangles.push_back({{a0, b1, b0}});
  }
  return m;
}

}  // namespace penumbra
