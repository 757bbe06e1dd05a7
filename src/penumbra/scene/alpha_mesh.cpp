#include "penumbra/scene/alpha_mesh.hpp"

#include "penumbra/core/error.hpp"
#include "penumbra/scene/material.hpp"

namespace penumbra {

bool is_uv_quad(const Mesh& m) {
  if (m.positions.size() != 4 || m.uvs.size() != 4 || m.triangles.size() != 2) return false;
  const Vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i)
    if (m.uvs[i] != uv[i]) return false;
  const Triangle& a = m.triangles[0];
  const Triangle& b = m.triangles[1];
  return a.v[0] == 0 && a.v[1] == 1 && a.v[2] == 2 && b.v[0] == 0 && b.v[1] == 2 && b.v[2] == 3;
}

Mesh mesh_alpha_runs(const Mesh& quad, const Texture& alpha) {
  const Vec3 p0 = quad.positions[0], eu = quad.positions[1] - p0, ev = quad.positions[3] - p0;
  auto at = [&](float u, float v) { return p0 + u * eu + v * ev; };
  Mesh out;
  out.name = quad.name + "_meshed";
  out.material = quad.material;
  out.casts_shadows = quad.casts_shadows;
  const float w = static_cast<float>(alpha.width), h = static_cast<float>(alpha.height);
  for (int y = 0; y < alpha.height; ++y) {
    for (int x = 0; x < alpha.width;) {
      if (alpha.channel(x, y, 0) < kAlphaCutoff) {
        ++x;
        continue;
      }
      int end = x;
      while (end < alpha.width && alpha.channel(end, y, 0) >= kAlphaCutoff) ++end;
      const float u0 = x / w, u1 = end / w, v0 = y / h, v1 = (y + 1) / h;
      const uint32_t base = static_cast<uint32_t>(out.positions.size());
      out.positions.insert(out.positions.end(), {at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1)});
      out.uvs.insert(out.uvs.end(), {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}});
      out.triangles.push_back({{base, base + 1, base + 2}});
      out.triangles.push_back({{base, base + 2, base + 3}});
      x = end;
    }
  }
  return out;
}

Scene with_meshed_alpha(const Scene& scene) {
  Scene out = scene;
  for (Mesh& mesh : out.meshes) {
    const Material& mat = scene.material_of(mesh);
    if (mat.alpha_texture < 0) continue;
    if (!is_uv_quad(mesh)) throw Error("meshed alpha: mesh '" + mesh.name + "' is not a uv quad");
    Material opaque = mat;
    opaque.name += "_meshed";
    opaque.alpha_texture = -1;
    out.materials.push_back(opaque);
    Mesh meshed = mesh_alpha_runs(mesh, scene.textures[mat.alpha_texture]);
    meshed.material = static_cast<int>(out.materials.size()) - 1;
    mesh = std::move(meshed);
  }
  return out;
}

}  // namespace penumbra
