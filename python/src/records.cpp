#include "records.hpp"

#include <cmath>
#include <cstdint>
#include <string>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "vehs/core/error.hpp"

namespace vehs::python {

Records records_from_arrays(InColumn x, const std::vector<std::size_t>& sizes, double dt,
                            std::optional<InColumn> u, const std::string& source) {
  require(std::isfinite(dt) && dt > 0, source + ": dt must be a finite number > 0");
  std::size_t total = 0;
  for (std::size_t n : sizes) total += n;
  require(total == x.shape(0), source + ": the record sizes add up to " + std::to_string(total) +
                                   " samples, x has " + std::to_string(x.shape(0)));
  require(!u || u->shape(0) == x.shape(0), source + ": u has " + std::to_string(u ? u->shape(0) : 0) +
                                               " samples, x has " + std::to_string(x.shape(0)));
  Records r;
  Dataset& d = *r.data;
  d.x.assign(x.data(), x.data() + x.shape(0));
  if (u) d.u.assign(u->data(), u->data() + u->shape(0));
  std::size_t offset = 0;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    Record rec;
    rec.source = source;
    rec.id = static_cast<long long>(i);
    rec.dt = dt;
    rec.offset = offset;
    rec.size = sizes[i];
    offset += sizes[i];
    d.records.push_back(rec);
  }
  return r;
}

Column column_view(Records&, std::vector<double>& column, nb::handle self) {
  const std::size_t shape[1] = {column.size()};
  return Column(column.data(), 1, shape, self);
}

void bind_records(nb::module_& m) {
  nb::class_<Records>(m, "Records", "Records in memory (a vehs::Dataset); NumPy views without copies.")
      .def_static("from_arrays", &records_from_arrays, nb::arg("x"), nb::arg("sizes"), nb::arg("dt"),
                  nb::arg("u").none() = nb::none(), nb::arg("source") = "array")
      .def_prop_ro("x", [](nb::handle_t<Records> self) {
        Records& r = nb::cast<Records&>(self);
        return column_view(r, r.data->x, self);
      })
      .def_prop_ro("y", [](nb::handle_t<Records> self) {
        Records& r = nb::cast<Records&>(self);
        return column_view(r, r.data->y, self);
      })
      .def_prop_ro("u", [](nb::handle_t<Records> self) {
        Records& r = nb::cast<Records&>(self);
        return column_view(r, r.data->u, self);
      })
      .def_prop_ro("sizes", [](const Records& r) {
        std::vector<std::size_t> s;
        for (const auto& rec : r.data->records) s.push_back(rec.size);
        return s;
      })
      .def_prop_ro("ids", [](const Records& r) {
        std::vector<long long> s;
        for (const auto& rec : r.data->records) s.push_back(rec.id);
        return s;
      })
      .def("address", [](const Records& r, const std::string& column) {
        const std::vector<double>& v = column == "y" ? r.data->y : column == "u" ? r.data->u : r.data->x;
        return reinterpret_cast<std::uintptr_t>(v.data());
      }, "Address of a column's memory in the library (to check that views are not copies).")
      .def_prop_ro("dt", [](const Records& r) { return r.data->common_dt(); });
}

}  // namespace vehs::python
