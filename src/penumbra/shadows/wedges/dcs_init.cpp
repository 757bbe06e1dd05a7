#include "penumbra/shadows/wedges/dcs_init.hpp"

#include <cmath>
#include <memory>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/orientation.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/shadows/wedges/pass.hpp"

namespace penumbra::dcs {

Image<int32_t> centre_counts(const ShadowContext& ctx, const std::vector<const Mesh*>& meshes,
                             const std::vector<const MeshEdges*>& edges, const Vec3& centre,
                             const ShadowVolumePixels& pixels) {
  std::vector<CountCaster> whole, facing;
  std::vector<std::unique_ptr<std::vector<uint8_t>>> keep;  // the facing faces, per closed mesh
  int winding = 0;  // Σ over the closed meshes of w(c) − w(camera)
  for (size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = *meshes[m];
    const MeshEdges& e = *edges[m];
    if (!e.closed_manifold() || ctx.scene.material_of(mesh).alpha_texture >= 0) {
      whole.push_back({&mesh, &e});
      continue;
    }
    const std::vector<int8_t> sides = face_sides(mesh, e, centre);
    auto facing_faces = std::make_unique<std::vector<uint8_t>>(sides.size());
    bool any = false;
    for (size_t f = 0; f < sides.size(); ++f) any |= ((*facing_faces)[f] = sides[f] > 0) != 0;
    // Closed meshes: the generalized winding numbers are integers up to rounding.
    winding +=
        static_cast<int>(std::lround(winding_number(mesh, e, DVec3(centre)))) -
        static_cast<int>(std::lround(winding_number(mesh, e, DVec3(ctx.scene.camera.position))));
    if (any) facing.push_back({&mesh, &e, facing_faces.get()});
    keep.push_back(std::move(facing_faces));
  }
  const GBuffer& g = ctx.gbuffer;
  Image<int32_t> out(g.width, g.height, 0);
  if (!whole.empty()) out = wedge_pass::hard_counts(ctx, whole, centre, &pixels);
  if (!facing.empty()) {
    const Image<int32_t> x = wedge_pass::hard_counts(ctx, facing, centre, &pixels);
    for (size_t i = 0; i < out.size(); ++i) out[i] += 2 * x[i];
  }
  if (winding != 0)
    for (size_t i = 0; i < out.size(); ++i)
      if (ctx.receivers[i] == kActive) out[i] += winding;
  return out;
}

}  // namespace penumbra::dcs
