// The pieces the built-in scenes are assembled from: materials, meshes, the ground, a square light.
#pragma once

#include <string>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Appends a material (`alpha_texture`: index into scene.textures, -1 for none); returns its index.
int add_material(Scene& s, const std::string& name, Vec3 albedo, int alpha_texture = -1);
/// Appends `mesh` under `name` with material index `material`.
void add_mesh(Scene& s, Mesh mesh, const std::string& name, int material);
/// The side×side ground quad at y = 0, facing up, centred on the origin.
void add_ground(Scene& s, float side = 10.0f);
/// A square light of side `side` centred at `center`, parallel to the ground, facing down.
Light square_light(const Vec3& center, float side, float power = 1.0f);
/// Appends `part`'s vertices (with its normals and uvs where `into` keeps them) and triangles to
/// `into`: many small shapes in one mesh.
void append_mesh(Mesh& into, const Mesh& part);

}  // namespace penumbra
