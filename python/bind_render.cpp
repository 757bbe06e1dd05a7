// Rendering from Python: render() and Renderer (the GIL released while the method runs), the
// result's NumPy arrays, compare(), methods(), read_image().
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "penumbra/io/image_io.hpp"
#include "penumbra/penumbra.hpp"

namespace py = pybind11;

namespace penumbra::python {

namespace {

/// A render's images as NumPy arrays, made once, and its statistics.
struct PyResult {
  RenderResult result;

  /// Per light H×W (one light) or L×H×W float32.
  py::array_t<float> visibility() const {
    const size_t lights = result.lights.size();
    const py::ssize_t h = result.surface.height(), w = result.surface.width();
    py::array_t<float> out = lights == 1
                                 ? py::array_t<float>({h, w})
                                 : py::array_t<float>({static_cast<py::ssize_t>(lights), h, w});
    float* dst = out.mutable_data();
    for (const Visibility& v : result.lights) {
      std::memcpy(dst, v.lit.data(), v.lit.size() * sizeof(float));
      dst += v.lit.size();
    }
    return out;
  }

  /// H×W×3 float32, linear RGB (None when render(beauty=False)).
  py::object beauty() const {
    if (result.beauty.empty()) return py::none();
    py::array_t<float> out({static_cast<py::ssize_t>(result.beauty.height()),
                            static_cast<py::ssize_t>(result.beauty.width()), py::ssize_t{3}});
    std::memcpy(out.mutable_data(), result.beauty.data(), result.beauty.size() * sizeof(Vec3));
    return out;
  }

  /// H×W×words uint64 (L×H×W×words for several lights): bit s of word s // 64 set = light
  /// sample s blocked. None when the method fills no masks.
  py::object masks() const {
    for (const Visibility& v : result.lights)
      if (!v.masks) return py::none();
    const SampleMasks& first = *result.lights.front().masks;
    const py::ssize_t h = first.height(), w = first.width(), words = first.words_per_pixel();
    const size_t lights = result.lights.size();
    py::array_t<uint64_t> out =
        lights == 1 ? py::array_t<uint64_t>({h, w, words})
                    : py::array_t<uint64_t>({static_cast<py::ssize_t>(lights), h, w, words});
    uint64_t* dst = out.mutable_data();
    const size_t per_light = static_cast<size_t>(h) * w * words;
    for (const Visibility& v : result.lights) {
      std::memcpy(dst, v.masks->pixel(0), per_light * sizeof(uint64_t));
      dst += per_light;
    }
    return out;
  }

  py::array_t<bool> surface() const {
    py::array_t<bool> out({static_cast<py::ssize_t>(result.surface.height()),
                           static_cast<py::ssize_t>(result.surface.width())});
    bool* dst = out.mutable_data();
    for (size_t i = 0; i < result.surface.size(); ++i) dst[i] = result.surface[i] != 0;
    return out;
  }

  /// Like stats.json: method, options, samples, times_ms (stages summed over lights, "total"),
  /// counters (a list per light when there are several), frame (the shared stages).
  py::dict stats() const {
    py::dict times, counters;
    py::list per_light;
    for (const Visibility& v : result.lights) {
      for (const auto& [stage, ms] : v.times.stages())
        times[py::str(stage)] =
            (times.contains(stage) ? py::cast<double>(times[py::str(stage)]) : 0.0) + ms;
      per_light.append(py::cast(v.counters));
    }
    times["total"] = result.method_ms;
    py::dict s;
    s["method"] = result.method;
    s["options"] = result.options;
    s["samples_per_pixel"] = result.samples_per_pixel;
    s["times_ms"] = times;
    s["prepare_ms"] = result.prepare_ms;
    s["counters"] = result.lights.size() == 1 ? per_light[0] : py::object(per_light);
    s["frame"] = result.frame_ms;
    return s;
  }
};

RenderSettings settings_of(const std::string& method, const std::optional<py::tuple>& size,
                           int samples, const std::string& pattern, uint64_t seed,
                           const std::optional<py::dict>& options, const std::string& backend,
                           std::optional<bool> masks, bool beauty) {
  RenderSettings s;
  s.method = method;
  if (size) {
    if (size->size() != 2) throw Error("size: expected (width, height)");
    s.width = py::cast<int>((*size)[0]);
    s.height = py::cast<int>((*size)[1]);
    // RenderSettings reads 0 × 0 as "the camera's size"; here a size is always given.
    if (s.width < 1 || s.height < 1)
      throw Error("size: expected WxH with 1..16384 pixels each, got " + std::to_string(s.width) +
                  "x" + std::to_string(s.height));
  }
  s.samples = samples;
  s.pattern = pattern;
  s.seed = seed;
  if (options)
    for (const auto& [key, value] : *options) {
      // Booleans as the CLI spells them; everything else through str().
      s.options[py::str(key)] = py::isinstance<py::bool_>(value)
                                    ? (value.cast<bool>() ? "true" : "false")
                                    : std::string(py::str(value));
    }
  s.backend = backend;
  const MethodInfo* info = MethodRegistry::builtin().find(method);
  s.masks = masks ? *masks : (info && info->sample_exact);
  s.beauty = beauty;
  return s;
}

PyResult render_with(Renderer& renderer, const Scene& scene, const RenderSettings& settings) {
  const Scene copy = scene;  // under the GIL: no Python thread edits it while it renders
  py::gil_scoped_release release;
  return PyResult{renderer.render(copy, settings)};
}

py::dict metrics_dict(const ErrorStats& e) {
  py::dict d;
  d["mean_abs_shadowed"] = e.mean_abs_shadowed;
  d["mean_abs"] = e.mean_abs;
  d["rmse"] = e.rmse;
  d["max_abs"] = e.max_abs;
  d["psnr"] = e.psnr;
  d["frac_over_1_255"] = e.frac_over_1_255;
  d["frac_over_1_16"] = e.frac_over_1_16;
  d["pixels"] = e.pixels;
  d["shadowed_pixels"] = e.shadowed_pixels;
  return d;
}

/// `penumbra compare`'s output: light 0's metrics, and "lights" (each light's) when several.
py::dict compare_dict(const std::vector<ErrorStats>& per_light) {
  py::dict d = metrics_dict(per_light.front());
  if (per_light.size() > 1) {
    py::list lights;
    for (const ErrorStats& e : per_light) lights.append(metrics_dict(e));
    d["lights"] = lights;
  }
  return d;
}

Image<float> to_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& a,
                      const char* what) {
  if (a.ndim() != 2) throw Error(std::string(what) + ": expected an H×W array");
  Image<float> img(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  std::memcpy(img.data(), a.data(), img.size() * sizeof(float));
  return img;
}

py::list methods_list() {
  py::list out;
  for (const MethodInfo& m : methods()) {
    py::list options;
    for (const OptionSpec& o : m.options) {
      static const char* kTypes[] = {"integer", "real", "boolean", "choice"};
      py::dict d;
      d["key"] = o.key;
      d["type"] = kTypes[static_cast<int>(o.type)];
      d["default"] = o.default_value;
      d["help"] = o.help;
      if (o.type == OptionType::choice) d["choices"] = o.choices;
      if (o.type == OptionType::integer || o.type == OptionType::real) {
        d["min"] = o.min;
        d["max"] = o.max;
      }
      options.append(d);
    }
    py::dict d;
    d["name"] = m.name;
    d["summary"] = m.summary;
    d["reference"] = m.reference;
    d["sample_exact"] = m.sample_exact;
    d["options"] = options;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_render(py::module_& m) {
  py::class_<PyResult>(m, "Result", "One method's render of a frame")
      .def_property_readonly("visibility", &PyResult::visibility,
                             "V in [0, 1]: float32 H×W, or L×H×W for several lights")
      .def_property_readonly("beauty", &PyResult::beauty, "float32 H×W×3, linear RGB")
      .def_property_readonly("masks", &PyResult::masks,
                             "uint64 H×W×words (L×H×W×words): bit s of word s//64 set = light "
                             "sample s blocked; None for methods that are not sample-exact")
      .def_property_readonly("surface", &PyResult::surface,
                             "bool H×W: True where a primary ray hit a mesh")
      .def_property_readonly("stats", &PyResult::stats,
                             "dict: method, options, times_ms, counters, frame (milliseconds)")
      .def_property_readonly("method", [](const PyResult& r) { return r.result.method; });

  const auto render_doc =
      "Renders `scene` with one method on every light. size=(width, height) overrides the "
      "camera's; samples=K gives K×K light samples; options are the method's (penumbra.methods()); "
      "masks defaults to True for sample-exact methods. Raises penumbra.Error on bad input.";
  py::class_<Renderer>(m, "Renderer",
                       "Keeps the BVH and every method's scene preparation across renders of "
                       "one scene's geometry (lights and camera may change)")
      .def(py::init<>())
      .def(
          "render",
          [](Renderer& self, const Scene& scene, const std::string& method,
             const std::optional<py::tuple>& size, int samples, const std::string& pattern,
             uint64_t seed, const std::optional<py::dict>& options, const std::string& backend,
             std::optional<bool> masks, bool beauty) {
            return render_with(
                self, scene,
                settings_of(method, size, samples, pattern, seed, options, backend, masks, beauty));
          },
          py::arg("scene"), py::arg("method") = "gears", py::arg("size") = py::none(),
          py::arg("samples") = 16, py::arg("pattern") = "grid", py::arg("seed") = 1,
          py::arg("options") = py::none(), py::arg("backend") = "cpu",
          py::arg("masks") = py::none(), py::arg("beauty") = true, render_doc);

  m.def(
      "render",
      [](const Scene& scene, const std::string& method, const std::optional<py::tuple>& size,
         int samples, const std::string& pattern, uint64_t seed,
         const std::optional<py::dict>& options, const std::string& backend,
         std::optional<bool> masks, bool beauty) {
        Renderer renderer;
        return render_with(
            renderer, scene,
            settings_of(method, size, samples, pattern, seed, options, backend, masks, beauty));
      },
      py::arg("scene"), py::arg("method") = "gears", py::arg("size") = py::none(),
      py::arg("samples") = 16, py::arg("pattern") = "grid", py::arg("seed") = 1,
      py::arg("options") = py::none(), py::arg("backend") = "cpu", py::arg("masks") = py::none(),
      py::arg("beauty") = true, render_doc);

  m.def(
      "compare",
      [](const PyResult& reference, const PyResult& test) {
        return compare_dict(compare(reference.result, test.result));
      },
      py::arg("reference"), py::arg("test"),
      "The metrics of `penumbra compare` of test against reference, over the reference's "
      "surface pixels: light 0's, and 'lights' (every light's) when there are several");
  m.def(
      "compare",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& reference,
         const py::array_t<float, py::array::c_style | py::array::forcecast>& test,
         const std::optional<py::array_t<float, py::array::c_style | py::array::forcecast>>& mask) {
        const Image<float> r = to_image(reference, "reference"), t = to_image(test, "test");
        std::optional<Image<float>> k;
        if (mask) k = to_image(*mask, "mask");
        return metrics_dict(compare_images(r, t, k ? &*k : nullptr));
      },
      py::arg("reference"), py::arg("test"), py::arg("mask") = py::none(),
      "The metrics of two H×W visibility arrays (pixels where mask > 0.5, when given)");
  m.def("methods", &methods_list,
        "Every method: name, summary, reference, sample_exact, options (key, type, default, "
        "help, choices or min/max)");
  m.def(
      "read_image",
      [](const std::string& path) {
        py::dict layers;
        for (FloatLayer& layer : read_float_image(path)) {
          py::array_t<float> a({static_cast<py::ssize_t>(layer.pixels.height()),
                                static_cast<py::ssize_t>(layer.pixels.width())});
          std::memcpy(a.mutable_data(), layer.pixels.data(), layer.pixels.size() * sizeof(float));
          layers[py::str(layer.name)] = a;
        }
        return layers;
      },
      py::arg("path"), "The layers of a float image (visibility.exr, .pfm) as {name: float32 H×W}");
}

}  // namespace penumbra::python
