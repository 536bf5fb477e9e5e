#pragma once
// Records held for Python: a shared vehs::Dataset whose columns NumPy views without copying.
// simulate() hands its Dataset over (no copy out); identify() and diagnose() read a Records'
// Dataset directly (no copy in). A C-contiguous float64 NumPy array becomes a Records without a
// copy either: the Dataset's columns view the array's memory (vehs::Column::view) and the Records
// holds the array, so it cannot be freed or resized while viewed (NumPy refuses to resize an
// array that is referenced); other arrays are converted (copied) once on the way in. Writing into
// a viewed array from another thread during a call is undefined, as NumPy's own rules say.
#include <memory>
#include <optional>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/fit/data_checks.hpp"

namespace vehs::python {
namespace nb = nanobind;

using Column = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
using ReadOnlyColumn = nb::ndarray<nb::numpy, const double, nb::ndim<1>>;
using InColumn = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

struct Records {
  std::shared_ptr<Dataset> data = std::make_shared<Dataset>();
  std::vector<InColumn> viewed;  ///< the arrays the Dataset's columns view, held while it lives
  bool checked = false;          ///< read by vehs.read, which ran the data checks already
};

/// The records identify and diagnose fit: `records` as they are when vehs.read checked them,
/// else after the data checks of identify-vehs and diagnose-vehs (glitches, flat stretches) under
/// the options' `glitches` and `flat_stretches` rules, so that arrays get the checks files get.
std::shared_ptr<const Dataset> checked_records(const Records& records, const tools::Config& options);
/// The same under typed rules (vehs.FitOptions' glitches and flat_stretches).
std::shared_ptr<const Dataset> checked_records(const Records& records, const DataChecks& checks);

/// A Dataset of records of the given sizes, all sampled every `dt` from t = 0, named `source` in
/// error messages, whose x (and u) view the arrays' memory (no copy).
Records records_from_arrays(InColumn x, const std::vector<std::size_t>& sizes, double dt,
                            std::optional<InColumn> u, const std::string& source);

/// A NumPy view of a column of a Records' Dataset (x, y or u: all records concatenated; empty
/// when the column is absent; read-only when the column itself views an array). `self` (the
/// Records) keeps the memory alive while the view lives.
nb::object column_view(const vehs::Column& column, nb::handle self);

void bind_records(nb::module_& m);

}  // namespace vehs::python
