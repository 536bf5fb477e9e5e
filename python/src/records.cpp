#include "records.hpp"

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "tools/data_checks.hpp"
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
  d.x = vehs::Column::view(x.data(), x.shape(0));
  r.viewed.push_back(x);
  if (u) {
    d.u = vehs::Column::view(u->data(), u->shape(0));
    r.viewed.push_back(*u);
  }
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

std::shared_ptr<const Dataset> checked_records(const Records& records, const tools::Config& options) {
  return checked_records(records, tools::data_checks(options));
}

std::shared_ptr<const Dataset> checked_records(const Records& records, const DataChecks& checks) {
  if (records.checked) return records.data;
  CheckedData checked = check_data(*records.data, checks);
  for (const std::string& line : checked.dropped) std::cerr << "warning: " << line << "\n";  // as the CLI says it
  return std::make_shared<const Dataset>(std::move(checked.data));
}

nb::object column_view(const vehs::Column& column, nb::handle self) {
  const std::size_t shape[1] = {column.size()};
  if (column.is_view()) return nb::cast(ReadOnlyColumn(column.data(), 1, shape, self));
  return nb::cast(Column(const_cast<double*>(column.data()), 1, shape, self));  // owned by the Records
}

void bind_records(nb::module_& m) {
  nb::class_<Records>(m, "Records", "Records in memory (a vehs::Dataset); NumPy views without copies.")
      .def_static("from_arrays", &records_from_arrays, nb::arg("x"), nb::arg("sizes"), nb::arg("dt"),
                  nb::arg("u").none() = nb::none(), nb::arg("source") = "array")
      .def_prop_ro("x", [](nb::handle_t<Records> self) {
        return column_view(nb::cast<const Records&>(self).data->x, self);
      })
      .def_prop_ro("y", [](nb::handle_t<Records> self) {
        return column_view(nb::cast<const Records&>(self).data->y, self);
      })
      .def_prop_ro("u", [](nb::handle_t<Records> self) {
        return column_view(nb::cast<const Records&>(self).data->u, self);
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
        const vehs::Column& v = column == "y" ? r.data->y : column == "u" ? r.data->u : r.data->x;
        return reinterpret_cast<std::uintptr_t>(v.data());
      }, "Address of a column's memory in the library (to check that views are not copies).")
      .def("is_view", [](const Records& r, const std::string& column) {
        return (column == "y" ? r.data->y : column == "u" ? r.data->u : r.data->x).is_view();
      }, "Whether a column views the caller's array (True) or is the library's own memory.")
      .def_prop_ro("dt", [](const Records& r) { return r.data->common_dt(); });
}

}  // namespace vehs::python
