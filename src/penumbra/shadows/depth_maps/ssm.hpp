// `ssm`: Soft Shadow Maps (Atty, Holzschuch, Lapierre, Hasenfratz, Hansen & Sillion 2006)
// [Atty 2006 §3]. The scene is split into occluders and receivers [Atty 2006 §3.1]; the occluders
// are rendered into an occluder map from the centre of the rectangular light, axis-aligned with it
// [Atty 2006 §3.2]; each occluder texel becomes a micro-patch parallel to the light at its depth;
// its penumbra extent is the rectangular pyramid of §3.3, and inside it every soft-shadow-map
// texel gets the area of the micro-patch back-projected onto the light [Atty 2006 §3.4]. The soft
// shadow map is then projected from the light centre onto the G-buffer pixels.
//
// This header exposes the light-space pieces (the light's frame, tangent windows, the map
// renderer, the per-patch occlusion and the FP16 emulation) so tests can check them in isolation.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"
#include "penumbra/scene/light.hpp"
#include "penumbra/scene/scene.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {
class MethodOptions;
}

namespace penumbra::ssm {

using DVec3 = glm::dvec3;

/// The light as the rectangle the algorithm assumes [Atty 2006 §3.1]: centre C_L, unit axes a, b
/// along its edges, unit n toward the side it emits to, side lengths lu, lv. Light space: a point
/// p has coordinates (x, y, z) = ((p−C)·a, (p−C)·b, (p−C)·n), z = its depth from the light plane.
/// Round lights become the square of the same area (disk: in its plane; sphere: facing `toward`);
/// a point light a square of side `min_size`.
struct LightRect {
  DVec3 c{0.0}, a{1, 0, 0}, b{0, 0, 1}, n{0, -1, 0};
  double lu = 1.0, lv = 1.0;

  DVec3 local(const DVec3& p) const {
    const DVec3 r = p - c;
    return {glm::dot(r, a), glm::dot(r, b), glm::dot(r, n)};
  }
};
LightRect light_rect(const Light& light, const DVec3& toward, double min_size);

/// An axis-aligned window of tangent space (x/z, y/z) seen from the light centre, cut into w × h
/// texels. Texel (i, j) covers tangents [tx0 + i·dx, tx0 + (i+1)·dx] × [ty1 − (j+1)·dy,
/// ty1 − j·dy] (row 0 at the top, +y up, like the other depth maps).
struct Window {
  double tx0 = -1, tx1 = 1, ty0 = -1, ty1 = 1;
  int w = 1, h = 1;

  double dx() const { return (tx1 - tx0) / w; }
  double dy() const { return (ty1 - ty0) / h; }
  double centre_x(int i) const { return tx0 + (i + 0.5) * dx(); }
  double centre_y(int j) const { return ty1 - (j + 0.5) * dy(); }
  /// Continuous texel coordinates of tangent (tx, ty): texel (i, j) spans [i, i+1) × [j, j+1).
  double to_u(double tx) const { return (tx - tx0) / dx(); }
  double to_v(double ty) const { return (ty1 - ty) / dy(); }
  bool empty() const { return !(tx1 > tx0) || !(ty1 > ty0); }
};

/// Which faces of the selected meshes a map keeps, and which depth wins per texel.
enum class MapFaces { front_nearest, back_nearest, back_furthest, all_nearest };

/// Depth (light-space z) per texel of the triangles of meshes[k] with select[k], rendered through
/// `window` from the light centre; +inf where none. Faces judged from C_L like depth_map.hpp
/// (front: cross(p1−p0, p2−p0) points toward the light). Triangles are clipped at z ≥ near.
/// Band-parallel and deterministic.
Image<float> render_light_map(const Scene& scene, const std::vector<bool>& select,
                              const LightRect& light, const Window& window, MapFaces faces,
                              double near);

/// Fraction of the light hidden from receiver point q = (qx, qy, zr) (light space) by the
/// micro-patch of centre (px, py), half-sizes (hx, hy), at depth zo (parallel to the light)
/// [Atty 2006 §3.4]: back-projects the patch from q onto the light plane, rescales the light to
/// [0,1]², and multiplies the two interval overlaps. 0 when zr ≤ zo. Finite for any finite input
/// with zr > zo (a patch touching the receiver gives a huge but finite scale, clamped overlaps).
double patch_occlusion(double px, double py, double hx, double hy, double zo, double qx, double qy,
                       double zr, double lu, double lv);

/// A micro-patch — an occluder-map texel, or a merged rectangle of equal-depth texels — at depth
/// zo, centre (px, py), half-sizes (hx, hy) in light space [Atty 2006 §3.2], with its penumbra
/// extent [§3.3] as the soft-shadow-map texels [i0, i1] × [j0, j1], and its first occluder-map
/// texel (the blending order).
struct Patch {
  double px, py, hx, hy, zo;
  int i0, i1, j0, j1;
  int order_i, order_j;
};

/// Step 4 of one pass [Atty 2006 §3.4]: the soft shadow map (sw.w × sw.h, zero-initialised) where
/// each texel holding a receiver (rmap finite) sums in float, in patch order, the patch_occlusion
/// of every patch whose extent holds it, at the texel centre's point of depth rmap. `touched` gets
/// the number of (patch, texel) pairs visited.
using Blend =
    std::function<Image<float>(const std::vector<Patch>& patches, const Window& sw,
                               const Image<float>& rmap, const LightRect& light, double& touched)>;

/// The `ssm` method with step 4 done by `blend` (the Vulkan backend's); fp16 blending keeps the
/// CPU's loop.
std::unique_ptr<ShadowMethod> make_ssm(const MethodOptions& options, Blend blend);

/// `x` rounded to IEEE binary16 (s10e5: 11 significant bits, overflow to ±inf, subnormals kept),
/// returned as float: the precision of the 2006 GPU blending [Atty 2006 App. A]. Round to nearest
/// even, or toward zero with `toward_zero` — the rule App. A states (X + ε = X whenever
/// ε < 2^-10·X, e.g. 0.5 + 1/2049 = 0.5), which the fp16 option applies to each blend.
float round_to_half(float x, bool toward_zero = false);

}  // namespace penumbra::ssm
