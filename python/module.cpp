// The `penumbra` Python module (docs/api.md#python): scenes, rendering to NumPy arrays, metrics.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "penumbra/penumbra.hpp"

namespace py = pybind11;

PYBIND11_MODULE(penumbra, m) {
  m.doc() =
      "Penumbra: soft shadows by every published real-time method, measured against an "
      "exact reference";
  m.attr("__version__") = penumbra::version();
  // penumbra::Error (bad scenes, settings, options) as penumbra.Error, a ValueError, with the
  // CLI's one-line message.
  py::register_exception<penumbra::Error>(m, "Error", PyExc_ValueError);
  penumbra::python::bind_scene(m);
  penumbra::python::bind_render(m);
}
