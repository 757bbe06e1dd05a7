// The scene types in Python: Scene, Camera, Light, Material, Mesh (from NumPy arrays). Vectors are
// read as tuples and set from any sequence of three numbers.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl_bind.h>

#include <string>

#include "bindings.hpp"
#include "penumbra/penumbra.hpp"

namespace py = pybind11;

namespace penumbra::python {

namespace {

py::tuple to_tuple(const Vec3& v) {
  return py::make_tuple(v.x, v.y, v.z);
}

Vec3 to_vec3(const py::object& value, const char* what) {
  const auto seq = py::cast<std::vector<float>>(value);
  if (seq.size() != 3)
    throw Error(std::string(what) + ": expected 3 numbers, got " + std::to_string(seq.size()));
  return Vec3(seq[0], seq[1], seq[2]);
}

/// A read-write property of type Vec3 over member `field` of T.
template <typename T>
void vec3_property(py::class_<T>& cls, const char* name, Vec3 T::*field, const char* doc) {
  cls.def_property(
      name, [field](const T& self) { return to_tuple(self.*field); },
      [field, name](T& self, const py::object& value) { self.*field = to_vec3(value, name); }, doc);
}

LightShape parse_shape(const std::string& name) {
  for (LightShape s : {LightShape::point, LightShape::rect, LightShape::disk, LightShape::sphere})
    if (to_string(s) == name) return s;
  throw Error("light shape: expected point, rect, disk or sphere, got " + quote(name));
}

/// A mesh from vertices (N×3 numbers) and triangles (M×3 vertex indices); the indices are checked
/// here, the rest by validate_scene when the scene renders.
Mesh make_mesh(const py::array_t<float, py::array::c_style | py::array::forcecast>& vertices,
               const py::array_t<int64_t, py::array::c_style | py::array::forcecast>& triangles,
               int material, const std::string& name, bool casts_shadows, bool receives_shadows) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw Error("mesh vertices: expected an N×3 array");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw Error("mesh triangles: expected an M×3 array of vertex indices");
  Mesh mesh;
  mesh.name = name;
  mesh.material = material;
  mesh.casts_shadows = casts_shadows;
  mesh.receives_shadows = receives_shadows;
  const auto v = vertices.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    mesh.positions.emplace_back(v(i, 0), v(i, 1), v(i, 2));
  const auto t = triangles.unchecked<2>();
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    Triangle tri{};
    for (int c = 0; c < 3; ++c) {
      const int64_t index = t(i, c);
      if (index < 0 || index >= v.shape(0))
        throw Error("mesh triangles: triangle " + std::to_string(i) + " has vertex index " +
                    std::to_string(index) + ", outside 0.." + std::to_string(v.shape(0) - 1));
      tri.v[c] = static_cast<uint32_t>(index);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

void bind_camera(py::module_& m) {
  py::class_<Camera> cls(m, "Camera",
                         "Pinhole camera: position, target, up, vertical field of view, size");
  cls.def(py::init<>());
  vec3_property(cls, "position", &Camera::position, "world position");
  vec3_property(cls, "target", &Camera::target, "the point it looks at");
  vec3_property(cls, "up", &Camera::up, "up direction");
  cls.def_readwrite("vfov_deg", &Camera::vfov_deg, "vertical field of view, degrees");
  cls.def_readwrite("width", &Camera::width, "image width, pixels");
  cls.def_readwrite("height", &Camera::height, "image height, pixels");
}

void bind_light(py::module_& m) {
  py::class_<Light> cls(m, "Light", "An area light (rect, disk, sphere) or a point light");
  cls.def(py::init<>());
  cls.def_readwrite("name", &Light::name);
  cls.def_property(
      "shape", [](const Light& l) { return std::string(to_string(l.shape)); },
      [](Light& l, const std::string& s) { l.shape = parse_shape(s); },
      "point, rect, disk or sphere");
  vec3_property(cls, "center", &Light::center, "world position of the centre");
  vec3_property(cls, "edge_u", &Light::edge_u, "rect: first full edge vector");
  vec3_property(cls, "edge_v", &Light::edge_v,
                "rect: second full edge vector (emits toward u × v)");
  vec3_property(cls, "normal", &Light::normal, "disk: the direction it emits toward");
  cls.def_readwrite("radius", &Light::radius, "disk, sphere: radius");
  vec3_property(cls, "radiance", &Light::radiance, "emitted radiance, linear RGB");
  cls.def_readwrite("two_sided", &Light::two_sided);
  cls.def_property_readonly("area", &Light::area, "emitting area, world units²");
}

void bind_material(py::module_& m) {
  py::class_<Material> cls(m, "Material", "Lambertian albedo; occluders may be semi-opaque");
  cls.def(py::init<>());
  cls.def_readwrite("name", &Material::name);
  vec3_property(cls, "albedo", &Material::albedo, "Lambertian reflectance, linear RGB");
  cls.def_readwrite("transmittance", &Material::transmittance,
                    "fraction of light passing each crossing (0 = opaque)");
  cls.def_readonly("alpha_texture", &Material::alpha_texture,
                   "index of the alpha texture, -1 for none (scene files set it)");
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh> cls(m, "Mesh", "A triangle mesh in world space");
  cls.def(py::init(&make_mesh), py::arg("vertices"), py::arg("triangles"), py::arg("material") = 0,
          py::arg("name") = "mesh", py::arg("casts_shadows") = true,
          py::arg("receives_shadows") = true,
          "vertices: N×3 world positions; triangles: M×3 vertex indices (counter-clockwise seen "
          "from the front)");
  cls.def_readwrite("name", &Mesh::name);
  cls.def_readwrite("material", &Mesh::material, "index into Scene.materials");
  cls.def_readwrite("casts_shadows", &Mesh::casts_shadows);
  cls.def_readwrite("receives_shadows", &Mesh::receives_shadows);
  cls.def_property_readonly("vertices", [](const Mesh& mesh) {
    py::array_t<float> out({static_cast<py::ssize_t>(mesh.positions.size()), py::ssize_t{3}});
    auto o = out.mutable_unchecked<2>();
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int c = 0; c < 3; ++c) o(i, c) = mesh.positions[i][c];
    return out;
  });
  cls.def_property_readonly("triangles", [](const Mesh& mesh) {
    py::array_t<int64_t> out({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t{3}});
    auto o = out.mutable_unchecked<2>();
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) o(i, c) = mesh.triangles[i].v[c];
    return out;
  });
}

}  // namespace

void bind_scene(py::module_& m) {
  bind_camera(m);
  bind_light(m);
  bind_material(m);
  bind_mesh(m);
  py::bind_vector<std::vector<Light>>(m, "LightList");
  py::bind_vector<std::vector<Material>>(m, "MaterialList");
  py::bind_vector<std::vector<Mesh>>(m, "MeshList");

  py::class_<Scene> cls(m, "Scene", "Meshes, materials, lights and the camera of one frame");
  cls.def(py::init<>());
  cls.def_readwrite("name", &Scene::name);
  cls.def_readwrite("camera", &Scene::camera);
  cls.def_readwrite("lights", &Scene::lights);
  cls.def_readwrite("materials", &Scene::materials);
  cls.def_readwrite("meshes", &Scene::meshes);
  vec3_property(cls, "ambient", &Scene::ambient, "constant ambient radiance, linear RGB");
  cls.def_property_readonly("triangle_count", &Scene::triangle_count);
  cls.def(
      "copy", [](const Scene& s) { return Scene(s); }, "an independent copy");
  cls.def("__repr__", [](const Scene& s) {
    return "<penumbra.Scene '" + s.name + "': " + std::to_string(s.meshes.size()) + " meshes, " +
           std::to_string(s.triangle_count()) + " triangles, " + std::to_string(s.lights.size()) +
           " lights, " + std::to_string(s.camera.width) + "x" + std::to_string(s.camera.height) +
           ">";
  });

  m.def(
      "load_scene", [](const std::string& name) { return load_scene(name); },
      py::arg("name_or_path"),
      "A built-in scene by name, a JSON scene file or a model file (OBJ, PLY, glTF, ...)");
  m.def("builtin_scenes", &builtin_scene_names, "The built-in scenes' names");
}

}  // namespace penumbra::python
