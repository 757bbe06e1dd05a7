// The Python module's parts, one function per file (module.cpp calls them in order).
#pragma once

#include <pybind11/pybind11.h>

#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/light.hpp"
#include "penumbra/scene/material.hpp"
#include "penumbra/scene/mesh.hpp"

// The scene's lists are bound as Python sequences whose items are the scene's own objects, so
// that `scene.lights[0].center = ...` edits the scene (not a copy).
PYBIND11_MAKE_OPAQUE(std::vector<penumbra::Light>)
PYBIND11_MAKE_OPAQUE(std::vector<penumbra::Material>)
PYBIND11_MAKE_OPAQUE(std::vector<penumbra::Mesh>)

namespace penumbra::python {

/// Scene, Camera, Light, Material, Mesh, load_scene, builtin_scenes.
void bind_scene(pybind11::module_& m);
/// render, Renderer, Result, compare, methods, read_image.
void bind_render(pybind11::module_& m);

}  // namespace penumbra::python
