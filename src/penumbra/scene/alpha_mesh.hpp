// Perforated quads as opaque geometry: the "equivalent geometry represented by meshes" that soft
// textured shadow volumes are measured against [Forest 2008 ch. 5 introduction, fig. 5.8]. Each
// row of texels of the alpha mask becomes one quad (two triangles) per run of consecutive opaque
// texels (alpha ≥ kAlphaCutoff, the nearest-texel rule every method uses), so the mesh blocks
// exactly the light the texture does. Used by bench/bench_stsv.cpp and tests/test_stsv.cpp.
#pragma once

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Is `mesh` a parallelogram laid out as make_quad makes it (corners p0, p0 + u, p0 + u + v,
/// p0 + v with uv (0,0), (1,0), (1,1), (0,1); triangles (0,1,2), (0,2,3))?
bool is_uv_quad(const Mesh& mesh);

/// The opaque texel runs of `alpha` over uv quad `quad` (is_uv_quad), as separate quads.
Mesh mesh_alpha_runs(const Mesh& quad, const Texture& alpha);

/// `scene` with every alpha-textured uv quad replaced by mesh_alpha_runs under a copy of its
/// material without the alpha texture. Throws Error for an alpha-textured mesh of another shape.
Scene with_meshed_alpha(const Scene& scene);

}  // namespace penumbra
