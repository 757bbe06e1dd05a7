#include "penumbra/render/embree_scene.hpp"

#include <chrono>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/core/simd.hpp"
#include "penumbra/core/stats.hpp"

namespace penumbra {

/// What a filter function needs to know about its geometry.
struct GeometryData {
  const Mesh* mesh = nullptr;
  const Texture* alpha = nullptr;  // null: no holes
  float transmittance = 0.0f;      // > 0: semi-opaque
};

namespace {

bool is_hole(const GeometryData& g, unsigned prim, float u, float v) {
  return g.alpha && g.alpha->sample_scalar(g.mesh->uv_at(prim, u, v)) < kAlphaCutoff;
}

/// Primary rays: holes in alpha-textured surfaces are invisible.
void intersect_filter(const RTCFilterFunctionNArguments* args) {
  const auto& g = *static_cast<const GeometryData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (is_hole(g, prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

/// Shadow rays: holes let light through; a semi-opaque surface multiplies the ray's transmittance
/// and lets it continue (Forest 2008 §4.3.3: each crossing attenuates).
void occlusion_filter(const RTCFilterFunctionNArguments* args) {
  const auto& g = *static_cast<const GeometryData*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const OcclusionContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (is_hole(g, prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i))) {
      args->valid[i] = 0;
      continue;
    }
    if (g.transmittance > 0.0f && ctx->transmittance) {
      const unsigned id = RTCRayN_id(args->ray, args->N, i);
      if (ctx->first_crossing(id, RTCHitN_geomID(args->hit, args->N, i), prim))
        ctx->transmittance[id] *= g.transmittance;
      args->valid[i] = 0;
    }
  }
}

void check_device(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw Error(std::string("Embree error during ") + what + " (code " + std::to_string(err) + ")");
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, BvhUpdate updates) : scene_(&scene) {
  for (const Mesh& mesh : scene.meshes)
    topology_.emplace_back(mesh.positions.size(), mesh.triangles.size());
  const auto device_start = std::chrono::steady_clock::now();
  // PENUMBRA_SIMD pins Embree to the same instruction set as Penumbra's own kernels, so the
  // ratios against `raytrace` compare like with like.
  const std::string isa = simd::embree_isa();
  device_ = rtcNewDevice(isa.empty() ? nullptr : ("isa=" + isa).c_str());
  if (!device_) throw Error("cannot create the Embree device");
  device_ms_ = elapsed_ms(device_start);
  const auto start = std::chrono::steady_clock::now();
  rtc_scene_ = rtcNewScene(device_);
  // Robust mode: watertight triangle tests, so shadow rays never leak through shared edges.
  rtcSetSceneFlags(rtc_scene_, RTC_SCENE_FLAG_ROBUST);
  // Refit needs Embree's two-level structure, which only a scene of RTC_BUILD_QUALITY_LOW builds
  // (one BVH per geometry, each refitted or rebuilt by its own quality, under a top level rebuilt
  // each commit); otherwise the scene is one BVH over every triangle, rebuilt whole each commit.
  rtcSetSceneBuildQuality(
      rtc_scene_, updates == BvhUpdate::refit ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM);

  geometry_data_.resize(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const Material& mat = scene.material_of(mesh);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.positions.size()));
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      vertices[3 * v + 0] = mesh.positions[v].x;
      vertices[3 * v + 1] = mesh.positions[v].y;
      vertices[3 * v + 2] = mesh.positions[v].z;
    }
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) indices[3 * t + c] = mesh.triangles[t].v[c];
    if (updates == BvhUpdate::refit) rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_REFIT);
    rtcSetGeometryMask(geom, mesh.casts_shadows ? (kMaskVisible | kMaskCaster) : kMaskVisible);

    GeometryData& g = geometry_data_[m];
    g.mesh = &mesh;
    g.alpha = mat.alpha_texture >= 0 ? &scene.textures[mat.alpha_texture] : nullptr;
    g.transmittance = mat.transmittance;
    if (g.alpha || g.transmittance > 0.0f) {
      has_filters_ = true;
      rtcSetGeometryUserData(geom, &g);
      rtcSetGeometryOccludedFilterFunction(geom, occlusion_filter);
      if (g.alpha) rtcSetGeometryIntersectFilterFunction(geom, intersect_filter);
    }
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(rtc_scene_, geom);
    rtcReleaseGeometry(geom);
    if (mesh_of_geom_.size() <= id) mesh_of_geom_.resize(id + 1, -1);
    mesh_of_geom_[id] = static_cast<int>(m);
    geom_of_mesh_.push_back(id);
  }
  rtcCommitScene(rtc_scene_);
  check_device(device_, "the BVH build");
  build_ms_ = elapsed_ms(start);
}

bool EmbreeScene::same_topology(const Scene& scene) const {
  if (scene.meshes.size() != topology_.size()) return false;
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    if (topology_[m] !=
        std::pair(scene.meshes[m].positions.size(), scene.meshes[m].triangles.size()))
      return false;
  return true;
}

void EmbreeScene::update(const Scene& scene) {
  if (!same_topology(scene))
    throw Error("BVH update: the scene's meshes differ from the BVH's (vertex or triangle counts)");
  const auto start = std::chrono::steady_clock::now();
  scene_ = &scene;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    GeometryData& g = geometry_data_[m];
    // The filters read uvs and textures through these: point them at the new scene's.
    g.mesh = &mesh;
    if (g.alpha) g.alpha = &scene.textures[scene.material_of(mesh).alpha_texture];
    RTCGeometry geom = rtcGetGeometry(rtc_scene_, geom_of_mesh_[m]);
    auto* vertices = static_cast<float*>(rtcGetGeometryBufferData(geom, RTC_BUFFER_TYPE_VERTEX, 0));
    bool moved = false;
    for (size_t v = 0; v < mesh.positions.size() && !moved; ++v)
      moved = vertices[3 * v] != mesh.positions[v].x ||
              vertices[3 * v + 1] != mesh.positions[v].y ||
              vertices[3 * v + 2] != mesh.positions[v].z;
    if (!moved) continue;  // a mesh the animation leaves still keeps its BVH
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      vertices[3 * v + 0] = mesh.positions[v].x;
      vertices[3 * v + 1] = mesh.positions[v].y;
      vertices[3 * v + 2] = mesh.positions[v].z;
    }
    rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(geom);
  }
  rtcCommitScene(rtc_scene_);
  check_device(device_, "the BVH update");
  build_ms_ = elapsed_ms(start);
}

EmbreeScene::~EmbreeScene() {
  if (rtc_scene_) rtcReleaseScene(rtc_scene_);
  if (device_) rtcReleaseDevice(device_);
}

}  // namespace penumbra
