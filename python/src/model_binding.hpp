#pragma once
#include <string>

#include <nanobind/nanobind.h>

#include "vehs/io/model_file.hpp"

namespace vehs::python {
namespace nb = nanobind;

/// A model file's content from JSON text; errors prefixed with `where`.
ModelFile model_from_text(const std::string& text, const std::string& where);

void bind_model(nb::module_& m);

}  // namespace vehs::python
