// Built-in scenes of the classes the papers measure beyond single dense models: fragmented
// geometry (`nest`, the Bird Nest of [Wang 2014 §4.3]), perforated foliage at scale (`garden`,
// Wang 2014's Garden; the textured occluders of [Forest 2008 ch. 5]) and many dense models side by
// side (`herd`). Procedural content is drawn from PCG32 with a fixed seed, so a name always gives
// the same triangles; the seed is a parameter here only so tests can tell seeds apart.
#pragma once

#include <cstdint>
#include <string>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

inline constexpr uint64_t kSceneClassSeed = 1;
// The built-in scenes' sizes; tests draw smaller ones of the same kind (a few seconds a frame).
inline constexpr int kNestTwigs = 20000;
inline constexpr int kGardenPlantsPerSide = 20;
inline constexpr int kHerdShapeSegments = 240;

/// `twigs` twigs (thin open triangular prisms, 6 triangles each, none sharing a vertex with
/// another) in a hemispherical bowl shell over the ground, lit from above and to the side.
Scene make_nest_scene(uint64_t seed = kSceneClassSeed, int twigs = kNestTwigs);

/// A bed of plants_per_side² plants: opaque stems, each with 256 alpha-textured leaf cards (2
/// triangles each; a procedural leaf-shaped alpha mask), over the ground.
Scene make_garden_scene(uint64_t seed = kSceneClassSeed,
                        int plants_per_side = kGardenPlantsPerSide);

/// Where `herd` takes its models from.
enum class HerdSource {
  automatic,   // the fetched CGAL models when all are present, else the procedural shapes
  procedural,  // bumpy spheres and tori, whatever is fetched
};

/// Six dense closed models in two rows of three, each turned about the vertical by a seeded angle.
/// The procedural shapes have `shape_segments` segments around (and half as many across): about
/// shape_segments² triangles each.
Scene make_herd_scene(uint64_t seed = kSceneClassSeed, HerdSource source = HerdSource::automatic,
                      int shape_segments = kHerdShapeSegments);

/// Are all of herd's CGAL models fetched (so that `automatic` uses them)?
bool herd_models_fetched();

/// One line on where herd's models come from now (the models found, or the procedural stand-ins
/// and how to fetch the models).
std::string herd_origin();

}  // namespace penumbra
