#pragma once
// The parts of the _vehs extension module, one per area.
#include <nanobind/nanobind.h>

#include "model_binding.hpp"

namespace vehs::python {
namespace nb = nanobind;

void bind_records(nb::module_& m);
void bind_read(nb::module_& m);
void bind_model(nb::module_& m);
void bind_simulate(nb::module_& m);
void bind_identify(nb::module_& m);
void bind_fpk(nb::module_& m);
void bind_diagnose(nb::module_& m);

}  // namespace vehs::python
