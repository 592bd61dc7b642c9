// hazmap._hazmap: the library for Python (python/hazmap/__init__.py re-exports it).
// A thin layer: every computation is the library's; this folder only converts numpy
// arrays and Python values and turns the library's errors into exceptions.

#include <pybind11/pybind11.h>

#include <spdlog/spdlog.h>

#include "bindings.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/map/dense_grid.hpp"

PYBIND11_MODULE(_hazmap, m) {
  namespace py = pybind11;
  m.doc() = "hazmap: stereo-to-hazard terrain mapping (see README.md, section Python)";
  m.attr("__version__") = HAZMAP_VERSION;
  // The library's expected failures (bad file, bad key, bad input) carry a one-line
  // message naming the file, line or key: it becomes the exception's message.
  py::register_exception<hazmap::Error>(m, "Error", PyExc_RuntimeError);
  // The library's log lines as the CLI prints them: the message alone, no timestamp.
  spdlog::set_pattern("%v");
  m.attr("UNKNOWN") = static_cast<int>(hazmap::HazardClass::unknown);
  m.attr("TRAVERSABLE") = static_cast<int>(hazmap::HazardClass::traversable);
  m.attr("HAZARD") = static_cast<int>(hazmap::HazardClass::hazard);
  hazmap::python::bind_maps(m);
  hazmap::python::bind_io_and_eval(m);
}
