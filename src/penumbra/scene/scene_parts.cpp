#include "penumbra/scene/scene_parts.hpp"

#include "penumbra/scene/shapes.hpp"

namespace penumbra {

int add_material(Scene& s, const std::string& name, Vec3 albedo, int alpha_texture) {
  Material m;
  m.name = name;
  m.albedo = albedo;
  m.alpha_texture = alpha_texture;
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size() - 1);
}

void add_mesh(Scene& s, Mesh mesh, const std::string& name, int material) {
  mesh.name = name;
  mesh.material = material;
  s.meshes.push_back(std::move(mesh));
}

void add_ground(Scene& s, float side) {
  const int mat = add_material(s, "ground", Vec3(0.75f));
  add_mesh(s, make_quad(Vec3(0.0f), Vec3(0, 0, side), Vec3(side, 0, 0)), "ground", mat);
}

Light square_light(const Vec3& center, float side, float power) {
  Light l;
  l.name = "light";
  l.shape = LightShape::rect;
  l.center = center;
  l.edge_u = Vec3(side, 0, 0);
  l.edge_v = Vec3(0, 0, side);  // cross(edge_u, edge_v) = -y: emits downward
  l.radiance = Vec3(power);
  return l;
}

void append_mesh(Mesh& into, const Mesh& part) {
  // Attributes stay only while every part so far has them (an empty mesh takes the first part's).
  const bool first = into.positions.empty();
  const uint32_t base = static_cast<uint32_t>(into.positions.size());
  into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
  if (!part.normals.empty() && (first || !into.normals.empty())) {
    into.normals.insert(into.normals.end(), part.normals.begin(), part.normals.end());
  } else {
    into.normals.clear();
  }
  if (!part.uvs.empty() && (first || !into.uvs.empty())) {
    into.uvs.insert(into.uvs.end(), part.uvs.begin(), part.uvs.end());
  } else {
    into.uvs.clear();
  }
  for (Triangle t : part.triangles) {
    for (uint32_t& v : t.v) v += base;
    into.triangles.push_back(t);
  }
}

}  // namespace penumbra
