// The scene's Embree BVH, shared by the G-buffer, the ray-traced reference and any method that
// traces rays. Alpha-textured and semi-opaque materials get occlusion filter functions.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

struct GeometryData;

/// What update() does to the BVH when the vertices move (a deforming or moving mesh).
enum class BvhUpdate {
  rebuild,  // a full build of every geometry's BVH, as the first (RTC_BUILD_QUALITY_MEDIUM)
  refit,    // Embree's two-level BVH (scene RTC_BUILD_QUALITY_LOW): each moved geometry's tree
            // kept, its boxes refitted to the new vertices (RTC_BUILD_QUALITY_REFIT)
};

class EmbreeScene {
 public:
  /// Builds the BVH over every mesh (static scene, RTC_BUILD_QUALITY_MEDIUM: no spatial splits, so
  /// an occlusion filter sees each triangle at most once per ray). `updates` says how update()
  /// will rebuild it: refit builds the two-level structure with every geometry of
  /// RTC_BUILD_QUALITY_REFIT.
  explicit EmbreeScene(const Scene& scene, BvhUpdate updates = BvhUpdate::rebuild);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const Scene& scene() const { return *scene_; }
  RTCScene handle() const { return rtc_scene_; }
  /// Wall time of the BVH build (or of the last update()), milliseconds.
  double build_ms() const { return build_ms_; }
  /// Whether `scene` has this BVH's meshes with the same vertex and triangle counts: what
  /// update() needs. Compared with the counts recorded at the build (the scene built from may be
  /// gone by then: an animation's previous pose).
  bool same_topology(const Scene& scene) const;
  /// Moves the vertices to those of `scene` (same topology, same materials: the next frame of an
  /// animation) and commits the scene again, rebuilding or refitting as constructed. `scene`
  /// replaces the one given before and must outlive every ray traced after. Throws Error when
  /// the topology differs. build_ms() then is this update's wall time.
  void update(const Scene& scene);
  /// Wall time of the Embree device's creation (its thread pool, CPU dispatch), milliseconds.
  double device_ms() const { return device_ms_; }
  /// Mesh index of an Embree geometry id.
  int mesh_of_geometry(unsigned geom_id) const { return mesh_of_geom_[geom_id]; }
  /// Does some material need filter callbacks (alpha or transmittance)?
  bool has_filtered_occluders() const { return has_filters_; }

  /// Embree ray mask bits: primary rays see everything, shadow rays only shadow casters.
  static constexpr unsigned kMaskVisible = 1u;
  static constexpr unsigned kMaskCaster = 2u;

 private:
  const Scene* scene_;
  std::vector<std::pair<size_t, size_t>> topology_;  // per mesh: vertices, triangles
  RTCDevice device_ = nullptr;
  RTCScene rtc_scene_ = nullptr;
  std::vector<int> mesh_of_geom_;
  std::vector<unsigned> geom_of_mesh_;
  std::vector<GeometryData> geometry_data_;  // filter-function user data, one per mesh
  double build_ms_ = 0.0;
  double device_ms_ = 0.0;
  bool has_filters_ = false;
};

/// Occlusion-ray context: an Embree intersect context extended with per-ray transmittance
/// accumulators (indexed by the ray id), which the semi-opaque filter multiplies.
///
/// Embree may call a filter several times for the same ray and triangle (measured: packet
/// traversal of a two-geometry scene calls it four times per hit), so each ray remembers the
/// triangles it was already attenuated by and counts each crossing once.
struct OcclusionContext {
  static constexpr int kMaxCrossings =
      16;  // remembered per ray; later crossings are not deduplicated

  RTCIntersectContext rtc;         // must stay first: Embree hands filters a pointer to it
  float* transmittance = nullptr;  // per ray id; nullptr when the scene has no semi-opaque material
  uint64_t* crossed = nullptr;     // per ray id: kMaxCrossings (geometry, triangle) keys
  uint8_t* crossed_count = nullptr;  // per ray id

  /// Returns true the first time ray `id` reports triangle (geom, prim).
  bool first_crossing(unsigned id, unsigned geom, unsigned prim) const {
    const uint64_t key = (uint64_t{geom} << 32) | prim;
    uint64_t* seen = crossed + static_cast<size_t>(id) * kMaxCrossings;
    uint8_t& count = crossed_count[id];
    for (int k = 0; k < count; ++k)
      if (seen[k] == key) return false;
    if (count < kMaxCrossings) seen[count++] = key;
    return true;
  }
};

/// Per-thread storage behind an OcclusionContext for up to `rays` rays with ids 0..rays-1.
class OcclusionScratch {
 public:
  explicit OcclusionScratch(int rays)
      : transmittance_(rays, 1.0f),
        crossed_(static_cast<size_t>(rays) * OcclusionContext::kMaxCrossings),
        crossed_count_(rays, 0) {}
  /// A coherent-ray context over this storage.
  OcclusionContext context() {
    OcclusionContext ctx;
    rtcInitIntersectContext(&ctx.rtc);
    ctx.rtc.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    ctx.transmittance = transmittance_.data();
    ctx.crossed = crossed_.data();
    ctx.crossed_count = crossed_count_.data();
    return ctx;
  }
  /// Resets ray `id` before it is traced.
  void reset(unsigned id) {
    transmittance_[id] = 1.0f;
    crossed_count_[id] = 0;
  }
  float transmittance(unsigned id) const { return transmittance_[id]; }

 private:
  std::vector<float> transmittance_;
  std::vector<uint64_t> crossed_;
  std::vector<uint8_t> crossed_count_;
};

}  // namespace penumbra
