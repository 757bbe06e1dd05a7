// A fingerprint of what a scene's preparation depends on (ShadowMethod::prepare, the Embree BVH):
// meshes, materials, textures and the recentring origin — not the lights, camera or ambient.
#pragma once

#include <cstdint>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// A 64-bit FNV-style hash, eight bytes a step, of every mesh (positions, normals, uvs, triangles,
/// material, roles), material and texture, and the scene's origin. Equal scenes give equal
/// hashes; a change of one word always changes it, of several but for a 2⁻⁶⁴ chance.
uint64_t geometry_hash(const Scene& scene);

}  // namespace penumbra
