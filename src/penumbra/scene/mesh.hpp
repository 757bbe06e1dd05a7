// Triangle meshes in world space (the scene loader applies each mesh's transform once).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

struct Triangle {
  uint32_t v[3];
};

struct Mesh {
  std::string name;
  std::vector<Vec3> positions;  // world space
  std::vector<Vec3> normals;    // optional per-vertex shading normals (empty: flat shading)
  std::vector<Vec2> uvs;  // optional per-vertex texture coordinates (needed by alpha textures)
  std::vector<Triangle> triangles;
  int material = 0;
  /// Occluder / receiver roles (the image-based methods split the scene, Atty 2006 §3.1).
  bool casts_shadows = true;
  bool receives_shadows = true;
  /// Where the mesh came from, if from a file: world positions = source_transform × the file's.
  /// Lets a scene be written back as a reference to the file (scene_writer.hpp).
  std::string source_file;
  Mat4 source_transform{1.0f};

  size_t triangle_count() const { return triangles.size(); }
  Bounds3 bounds() const;
  Vec3 vertex(size_t tri, int corner) const { return positions[triangles[tri].v[corner]]; }
  /// Texture coordinate at barycentric (u, v) of triangle `tri` (Embree's convention:
  /// p = (1-u-v) p0 + u p1 + v p2). Zero when the mesh has no UVs.
  Vec2 uv_at(size_t tri, float u, float v) const {
    if (uvs.empty()) return Vec2(0.0f);
    const Triangle& t = triangles[tri];
    return (1.0f - u - v) * uvs[t.v[0]] + u * uvs[t.v[1]] + v * uvs[t.v[2]];
  }
};

/// Applies an affine model-to-world matrix: positions by M, normals by the inverse transpose of
/// M's 3×3 (renormalised), and a mirroring M (negative determinant) reverses each triangle so
/// faces keep facing outward. Scene files and model framing share it, so both give the same
/// floats.
void transform_mesh(Mesh& mesh, const Mat4& m);

/// A triangle is degenerate when its area vanishes relative to its longest edge, in double:
/// |e1 × e2| ≤ 1e-10 · L². Relative, so a 5e9 quad and a 1e-12 one survive alike; only collapsed
/// vertices and collinear corners (to well below float rounding) go.
bool is_degenerate(const Mesh& mesh, const Triangle& t);

}  // namespace penumbra
