// `raytrace`: the ray-traced reference. One Embree occlusion ray from each pixel's shadow origin to
// each light sample of the shared LightSamples; alpha holes and semi-opaque transmittance through
// the EmbreeScene filter functions. A pixel's rays share one origin, so they go out as coherent
// 16-wide packets (rtcOccluded16): on this hardware class about 3× faster than single rays.
#include <atomic>
#include <chrono>
#include <memory>
#include <utility>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/light_weights.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

constexpr int kPacket = 16;

class Raytrace final : public ShadowMethod {
 public:
  explicit Raytrace(const MethodOptions& options)
      : packets_(options.get_choice("path") == "packet16"), bvh_(options.get_choice("bvh")) {}

  /// With bvh=rebuild or refit the method keeps a BVH of its own, built at the first prepare()
  /// and updated at each later one (an animation's next pose): its cost is the method's, stage
  /// `bvh_update` of the next compute. With bvh=shared it traces the frame's BVH.
  void prepare(const Scene& scene) override {
    if (bvh_ == "shared") return;
    const auto start = std::chrono::steady_clock::now();
    if (own_ && own_->same_topology(scene))
      own_->update(scene);
    else
      own_ = std::make_unique<EmbreeScene>(scene,
                                           bvh_ == "refit" ? BvhUpdate::refit : BvhUpdate::rebuild);
    unreported_bvh_ms_ = elapsed_ms(start);
  }

  Visibility compute(const ShadowContext& ctx) override {
    const EmbreeScene* bvh = own_ ? own_.get() : ctx.embree;
    if (!bvh) throw Error("method 'raytrace' needs the scene's Embree BVH");
    const GBuffer& g = ctx.gbuffer;
    const int n = ctx.samples.count();
    // A point light has one position: trace one ray per pixel and copy its answer to every sample.
    const bool point = ctx.light.shape == LightShape::point;
    const int traced = point ? 1 : n;
    const Texture* emission =
        ctx.light.is_textured() ? &ctx.scene.textures[ctx.light.emission_texture] : nullptr;

    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    if (emission) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));
    if (ctx.want_masks) vis.masks = SampleMasks(g.width, g.height, n);
    std::atomic<uint64_t> rays{0};
    Progress progress("raytrace", static_cast<size_t>(g.height));
    const auto start = std::chrono::steady_clock::now();

    parallel_rows(g.height, [&](int y) {
      std::vector<Vec2> light_uv(n);
      std::vector<float> sample_vis(n);
      OcclusionScratch scratch(kPacket);
      uint64_t row_rays = 0;
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (ctx.receivers[i] != kActive) continue;
        const Vec3 origin = g.shadow_origin(i);
        const LightFrame frame = light_frame(ctx.light, origin);
        ctx.samples.pixel_samples(x, y, light_uv);
        row_rays +=
            trace_pixel(*bvh, origin, frame, light_uv.data(), traced, sample_vis.data(), scratch);
        if (point) std::fill(sample_vis.begin() + 1, sample_vis.end(), sample_vis[0]);

        const SampleWeights w =
            accumulate_sample_weights(frame, emission, ctx.light.radiance, light_uv, sample_vis);
        vis.lit[i] = w.visible_fraction();
        if (emission) vis.lit_rgb->operator[](i) = w.visible_fraction_rgb();
        if (vis.masks) {
          for (int s = 0; s < n; ++s)
            if (sample_vis[s] == 0.0f && frame.emits(light_uv[s])) vis.masks->set_blocked(i, s);
        }
      }
      rays += row_rays;
      progress.advance();
    });
    const double ms = elapsed_ms(start);
    vis.times.add("visibility", ms);
    vis.counters["rays"] = static_cast<double>(rays.load());
    vis.counters["rays_per_second"] =
        ms > 0.0 ? static_cast<double>(rays.load()) / (ms * 1e-3) : 0.0;
    vis.counters["bvh_build_ms"] = bvh->build_ms();
    // The own BVH's build or update, once, in the compute after it.
    if (own_) vis.times.add("bvh_update", std::exchange(unreported_bvh_ms_, 0.0));
    return vis;
  }

 private:
  /// Fills sample_vis[0..count) with each ray's transmitted fraction (0 blocked, 1 free).
  uint64_t trace_pixel(const EmbreeScene& bvh, const Vec3& origin, const LightFrame& frame,
                       const Vec2* light_uv, int count, float* sample_vis,
                       OcclusionScratch& scratch) const {
    OcclusionContext occ = scratch.context();
    uint64_t traced = 0;
    for (int base = 0; base < count; base += kPacket) {
      const int lanes = std::min(kPacket, count - base);
      if (packets_) {
        alignas(64) RTCRay16 ray;
        alignas(64) int valid[kPacket];
        for (int l = 0; l < kPacket; ++l) {
          const int s = base + l;
          valid[l] = (l < lanes && frame.emits(light_uv[s])) ? -1 : 0;
          const Vec3 dir = l < lanes ? frame.point(light_uv[s]) - origin : Vec3(0.0f, 1.0f, 0.0f);
          ray.org_x[l] = origin.x;
          ray.org_y[l] = origin.y;
          ray.org_z[l] = origin.z;
          ray.dir_x[l] = dir.x;
          ray.dir_y[l] = dir.y;
          ray.dir_z[l] = dir.z;
          ray.tnear[l] = 0.0f;
          ray.tfar[l] = static_cast<float>(kShadowSegmentEnd);  // the tie rule (method.hpp)
          ray.time[l] = 0.0f;
          ray.mask[l] = EmbreeScene::kMaskCaster;
          ray.id[l] = static_cast<unsigned>(l);
          ray.flags[l] = 0;
          scratch.reset(static_cast<unsigned>(l));
          traced += valid[l] != 0;
        }
        rtcOccluded16(valid, bvh.handle(), &occ.rtc, &ray);
        for (int l = 0; l < lanes; ++l)
          sample_vis[base + l] =
              valid[l] == 0 ? 0.0f : (ray.tfar[l] < 0.0f ? 0.0f : scratch.transmittance(l));
      } else {
        for (int l = 0; l < lanes; ++l) {
          const int s = base + l;
          sample_vis[s] = 0.0f;
          if (!frame.emits(light_uv[s])) continue;
          const Vec3 dir = frame.point(light_uv[s]) - origin;
          RTCRay ray{};
          ray.org_x = origin.x;
          ray.org_y = origin.y;
          ray.org_z = origin.z;
          ray.dir_x = dir.x;
          ray.dir_y = dir.y;
          ray.dir_z = dir.z;
          ray.tnear = 0.0f;
          ray.tfar = static_cast<float>(kShadowSegmentEnd);
          ray.mask = EmbreeScene::kMaskCaster;
          ray.id = static_cast<unsigned>(l);
          scratch.reset(static_cast<unsigned>(l));
          rtcOccluded1(bvh.handle(), &occ.rtc, &ray);
          sample_vis[s] = ray.tfar < 0.0f ? 0.0f : scratch.transmittance(l);
          ++traced;
        }
      }
    }
    return traced;
  }

  bool packets_;
  std::string bvh_;  // shared | rebuild | refit
  std::unique_ptr<EmbreeScene> own_;
  double unreported_bvh_ms_ = 0.0;
};

}  // namespace

void register_raytrace(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "raytrace";
  info.summary = "Embree occlusion rays to every light sample (the sampled reference)";
  info.reference = "the sampled reference: Embree [Wald 2014] (docs/references.md)";
  info.sample_exact = true;
  info.options = {{"path",
                   OptionType::choice,
                   "packet16",
                   "Embree path: coherent 16-wide packets per pixel, or single rays",
                   {"packet16", "single"}},
                  {"bvh",
                   OptionType::choice,
                   "shared",
                   "BVH traced: the frame's (shared, built outside the method's time), or one of "
                   "its own built in prepare and, when an animation moves the geometry, rebuilt or "
                   "refitted each frame inside its time (stage bvh_update; render --frames makes "
                   "shared rebuild then)",
                   {"shared", "rebuild", "refit"}}};
  info.create = [](const MethodOptions& o) { return std::make_unique<Raytrace>(o); };
  registry.add(std::move(info));
}

}  // namespace penumbra
