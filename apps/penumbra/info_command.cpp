// `penumbra info SCENE`: what a scene holds, and whether each mesh is closed 2-manifold.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/topology.hpp"

namespace penumbra::cli {

namespace {

/// One line on the scene's animation (render --frames takes frame indices 0 .. frames − 1).
void print_animation(const Scene& scene) {
  const Animation& a = scene.animation;
  if (a.empty()) return;
  std::string moves;
  if (a.moves_geometry()) moves += " geometry (" + std::to_string(a.meshes.size()) + " mesh(es))";
  if (a.moves_lights()) moves += " lights";
  if (a.moves_camera()) moves += " camera";
  std::printf("animation  %.4g s to %.4g s at %.4g fps: frames 0..%d; moves%s\n", a.start_s,
              a.end_s, a.fps, a.frame_count() - 1, moves.c_str());
}

/// A name from the scene file, safe for one terminal line (control characters escaped, cut).
std::string shown(const std::string& name) {
  return one_line(name, 80);
}

void run_info(const std::string& name) {
  const Scene scene = load_scene(name);
  const Bounds3 b = scene.bounds();
  std::printf("scene      %s\n", shown(scene.name).c_str());
  if (is_builtin_scene(name)) std::printf("origin     %s\n", builtin_scene_origin(name).c_str());
  std::printf("triangles  %zu in %zu mesh(es)\n", scene.triangle_count(), scene.meshes.size());
  if (scene.origin != DVec3(0.0))
    std::printf(
        "origin     (%.17g, %.17g, %.17g): bounds, camera and lights below are relative to it\n",
        scene.origin.x, scene.origin.y, scene.origin.z);
  std::printf("bounds     (%.4g, %.4g, %.4g) - (%.4g, %.4g, %.4g), diagonal %.4g\n", b.lo.x, b.lo.y,
              b.lo.z, b.hi.x, b.hi.y, b.hi.z, b.diagonal());
  std::printf("camera     (%.3g, %.3g, %.3g) -> (%.3g, %.3g, %.3g), fov %.3g deg, %dx%d\n",
              scene.camera.position.x, scene.camera.position.y, scene.camera.position.z,
              scene.camera.target.x, scene.camera.target.y, scene.camera.target.z,
              scene.camera.vfov_deg, scene.camera.width, scene.camera.height);
  for (const Mesh& m : scene.meshes) {
    const MeshTopology t = analyze_topology(m);
    const Material& mat = scene.material_of(m);
    std::printf("mesh       %-12s %8zu triangles  %s", shown(m.name).c_str(), m.triangle_count(),
                t.closed_manifold ? "closed 2-manifold" : "open/non-manifold");
    if (!t.closed_manifold)
      std::printf(" (%zu boundary, %zu non-manifold, %zu inconsistent edges)", t.boundary_edges,
                  t.non_manifold_edges, t.inconsistent_edges);
    if (mat.alpha_texture >= 0) std::printf(", alpha-textured");
    if (mat.transmittance > 0.0f) std::printf(", transmittance %.3g", mat.transmittance);
    if (!m.casts_shadows) std::printf(", casts no shadows");
    std::printf("\n");
  }
  for (const Light& l : scene.lights) {
    std::printf("light      %-12s %-6s centre (%.3g, %.3g, %.3g)", shown(l.name).c_str(),
                std::string(to_string(l.shape)).c_str(), l.center.x, l.center.y, l.center.z);
    if (l.shape == LightShape::rect)
      std::printf(", %.3g x %.3g", glm::length(l.edge_u), glm::length(l.edge_v));
    if (l.shape == LightShape::disk || l.shape == LightShape::sphere)
      std::printf(", radius %.3g", l.radius);
    if (l.is_textured()) std::printf(", textured");
    std::printf(", radiance (%.3g, %.3g, %.3g)\n", l.radiance.x, l.radiance.y, l.radiance.z);
  }
  print_animation(scene);
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto scene = std::make_shared<std::string>();
  auto scene_option = std::make_shared<std::string>();
  CLI::App* cmd =
      app.add_subcommand("info", "Describe a scene: triangles, bounds, lights, mesh topology");
  // The scene as the other commands take it (--scene) or positionally, one of the two.
  CLI::Option* positional =
      cmd->add_option("SCENE", *scene, "Built-in scene name, scene .json file or model file");
  CLI::Option* named = cmd->add_option("--scene", *scene_option, "The same, as render takes it");
  positional->excludes(named);
  cmd->callback([scene, scene_option, positional, named] {
    if (positional->count() == 0 && named->count() == 0)
      throw Error("info: a scene is required (penumbra info SCENE or penumbra info --scene SCENE)");
    run_info(positional->count() > 0 ? *scene : *scene_option);
  });
}

}  // namespace penumbra::cli
