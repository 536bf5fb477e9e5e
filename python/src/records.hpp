#pragma once
// Records held for Python: a shared vehs::Dataset whose columns NumPy views without copying.
// simulate() hands its Dataset over (no copy out); identify() and diagnose() read a Records'
// Dataset directly (no copy in). Plain NumPy arrays become a Records by one copy (the library's
// Dataset owns std::vector columns).
#include <memory>
#include <optional>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "vehs/core/dataset.hpp"

namespace vehs::python {
namespace nb = nanobind;

using Column = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
using InColumn = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

struct Records {
  std::shared_ptr<Dataset> data = std::make_shared<Dataset>();
};

/// One copy of the concatenated x (and u) into a Dataset of records of the given sizes, all
/// sampled every `dt` from t = 0, named `source` in error messages.
Records records_from_arrays(InColumn x, const std::vector<std::size_t>& sizes, double dt,
                            std::optional<InColumn> u, const std::string& source);

/// A view of a column of `owner`'s Dataset (x, y or u: all records concatenated); empty when
/// the column is absent. `self` keeps the Records alive while the view lives.
Column column_view(Records& owner, std::vector<double>& column, nb::handle self);

void bind_records(nb::module_& m);

}  // namespace vehs::python
