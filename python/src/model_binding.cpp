// vehs.Model in C++: the library's Model and the file sections it does not interpret, from and
// to JSON (the model file format), built by ModelBuilder, parameters by physical name.
#include "model_binding.hpp"

#include <cmath>

#include <nanobind/stl/map.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "bridge.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/model_builder.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/io/parameter_units.hpp"

namespace vehs::python {

ModelFile model_from_text(const std::string& text, const std::string& where) {
  ModelFile f;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": not a JSON model: " + e.what());
  }
  f.model = model_from_json(j, where, &f.sections);
  return f;
}

namespace {

using Terms = std::vector<std::pair<std::string, double>>;
using Effects = std::vector<std::pair<std::string, std::map<std::string, double>>>;

ModelFile build_model(const Terms& drift, const Terms& diffusion, const Terms& parameters, const Effects& effects,
                      const std::string& where) {
  ModelBuilder b(where);
  for (const auto& [term, c] : drift) b.drift(term, c);
  for (const auto& [term, c] : diffusion) b.diffusion(term, c);
  for (const auto& [name, v] : parameters) b.parameter(name, v);
  for (const auto& [name, params] : effects) b.effect(name, params);
  ModelFile f;
  f.model = b.build();
  return f;
}

}  // namespace

void bind_model(nb::module_& m) {
  nb::class_<ModelFile>(m, "Model", "A vehs model and the sections of its file (vehs::ModelFile).")
      .def_static("from_json", &model_from_text, nb::arg("text"), nb::arg("where") = "model")
      .def_static("build", &build_model, nb::arg("drift"), nb::arg("diffusion"), nb::arg("parameters"),
                  nb::arg("effects"), nb::arg("where") = "model")
      .def("to_json", [](const ModelFile& f) { return json_text(model_to_json(f.model, f.sections)); })
      .def("get", [](const ModelFile& f, const std::string& name) { return get_parameter(f.model, name); })
      .def("set", [](ModelFile& f, const std::string& name, double v) { set_parameter(f.model, name, v); })
      .def("parameters", [](const ModelFile& f) {  // the CLI's tables' rows (vehs/io/parameter_units.hpp)
        std::vector<std::tuple<std::string, double, double, std::string>> out;
        for (const auto& [p, unit] : parameter_rows(f.model, units_of(f.sections)))
          out.emplace_back(p.name, p.value, p.stderr_ ? *p.stderr_ : std::nan(""), unit);
        return out;
      })
      .def("b2", [](const ModelFile& f, double x, double y, double u) { return f.model.b2(x, y, u); })
      .def("a22", [](const ModelFile& f, double x, double y) { return f.model.a22(x, y); })
      .def("__copy__", [](const ModelFile& f) { return ModelFile(f); });
  // the unit rule of the tools' tables, for vehs.plot's axis labels (vehs/io/parameter_units.hpp)
  m.def(
      "unit_text",
      [](int length, int time, int input, const std::string& units) {
        return unit_text(Dimension{length, time, input}, nlohmann::json::parse(units));
      },
      nb::arg("length"), nb::arg("time"), nb::arg("input"), nb::arg("units"),
      "length^a time^b input^c in the names of a units block (JSON): \"mm/s^2\", \"1\" when dimensionless.");
  m.def(
      "parameter_unit",
      [](const std::string& name, const std::string& units) { return parameter_unit(name, nlohmann::json::parse(units)); },
      nb::arg("name"), nb::arg("units"), "The unit of a physical parameter (beta, k3, coulomb_friction.mu, ...).");
}

}  // namespace vehs::python
