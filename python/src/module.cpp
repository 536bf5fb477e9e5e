// The _vehs extension module: the library's types and functions for the pure-Python package
// vehs (python/vehs), which wraps them in a NumPy-friendly API. Errors are vehs.Error
// (a ValueError) with the library's one-line messages.
#include <nanobind/nanobind.h>

#include "bindings.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parallel.hpp"

NB_MODULE(_vehs, m) {
  namespace nb = nanobind;
  m.attr("__version__") = VEHS_VERSION;  // project(VERSION) of CMakeLists.txt, as the tools' --version
  nb::exception<vehs::Error>(m, "Error", PyExc_ValueError);
  m.def("set_threads", &vehs::set_threads, nb::arg("threads"), "Threads of the library's parallel loops (0: default).");
  m.def("max_threads", &vehs::max_threads);
  vehs::python::bind_records(m);
  vehs::python::bind_read(m);
  vehs::python::bind_model(m);
  vehs::python::bind_simulate(m);
  vehs::python::bind_identify(m);
  vehs::python::bind_fpk(m);
  vehs::python::bind_diagnose(m);
}
