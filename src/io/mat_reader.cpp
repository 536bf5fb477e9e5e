// MATLAB .mat files (v4, v5, v7.3) through libmatio: either one numeric vector per column, named
// like the CSV columns (t, x, u, traj), or one 2-D matrix (ReadOptions::mat_variable) whose
// columns ReadOptions::columns names. MATLAB loads such files whole, and so does this reader.
#include <dlfcn.h>
#include <matio.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "readers.hpp"
#include "vehs/core/error.hpp"

namespace vehs::io_detail {

namespace {

struct MatCloser {
  void operator()(mat_t* m) const {
    if (m) Mat_Close(m);
  }
};
struct VarFree {
  void operator()(matvar_t* v) const {
    if (v) Mat_VarFree(v);
  }
};
using MatFile = std::unique_ptr<mat_t, MatCloser>;
using MatVar = std::unique_ptr<matvar_t, VarFree>;

/// While in scope, HDF5's printing of its error stack (a corrupt v7.3 file: 14 lines of
/// "HDF5-DIAG" on stderr) is replaced on this thread by a flag, which the reader turns into one
/// line. libmatio reads v7.3 files through HDF5 when built with it; HDF5's H5Eget_auto2 and
/// H5Eset_auto2 are looked up at run time among libmatio's own dependencies (vehs does not link
/// HDF5), so without HDF5 nothing happens.
class Hdf5ErrorCapture {
 public:
  Hdf5ErrorCapture() {
    const Api& api = hdf5();
    if (!api.set || !api.get || api.get(kDefaultStack, &old_func_, &old_data_) < 0) return;
    active_ = api.set(kDefaultStack, &note, &failed_) >= 0;
  }
  ~Hdf5ErrorCapture() {
    if (active_) hdf5().set(kDefaultStack, old_func_, old_data_);
  }
  Hdf5ErrorCapture(const Hdf5ErrorCapture&) = delete;
  Hdf5ErrorCapture& operator=(const Hdf5ErrorCapture&) = delete;
  /// HDF5 reported an error since the capture began.
  bool failed() const { return failed_; }

 private:
  using Hid = std::int64_t;                   // hid_t (HDF5 >= 1.10)
  using AutoFunc = int (*)(Hid, void*);       // H5E_auto2_t
  static constexpr Hid kDefaultStack = 0;     // H5E_DEFAULT
  struct Api {
    int (*get)(Hid, AutoFunc*, void**) = nullptr;
    int (*set)(Hid, AutoFunc, void*) = nullptr;
  };
  static int note(Hid, void* failed) {
    *static_cast<bool*>(failed) = true;
    return 0;
  }
  static const Api& hdf5() {
    static const Api api = [] {
      Api a;
      Dl_info info{};
      if (!::dladdr(reinterpret_cast<void*>(&Mat_Open), &info) || !info.dli_fname) return a;
      void* matio = ::dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);  // searched with its dependencies
      if (!matio) return a;
      a.get = reinterpret_cast<decltype(a.get)>(::dlsym(matio, "H5Eget_auto2"));
      a.set = reinterpret_cast<decltype(a.set)>(::dlsym(matio, "H5Eset_auto2"));
      return a;
    }();
    return api;
  }
  AutoFunc old_func_ = nullptr;
  void* old_data_ = nullptr;
  bool active_ = false, failed_ = false;
};

template <class T>
std::vector<double> convert(const void* data, std::size_t n) {
  const T* p = static_cast<const T*>(data);
  return std::vector<double>(p, p + n);
}

/// All values of a real numeric variable, in MATLAB's column-major order.
std::vector<double> numbers(const matvar_t& v, const std::string& where) {
  if (v.isComplex) throw Error(where + " is complex");
  std::size_t n = 1;
  for (int i = 0; i < v.rank; ++i) n *= v.dims[i];
  switch (v.class_type) {
    case MAT_C_DOUBLE: return convert<double>(v.data, n);
    case MAT_C_SINGLE: return convert<float>(v.data, n);
    case MAT_C_INT8: return convert<std::int8_t>(v.data, n);
    case MAT_C_UINT8: return convert<std::uint8_t>(v.data, n);
    case MAT_C_INT16: return convert<std::int16_t>(v.data, n);
    case MAT_C_UINT16: return convert<std::uint16_t>(v.data, n);
    case MAT_C_INT32: return convert<std::int32_t>(v.data, n);
    case MAT_C_UINT32: return convert<std::uint32_t>(v.data, n);
    case MAT_C_INT64: return convert<std::int64_t>(v.data, n);
    case MAT_C_UINT64: return convert<std::uint64_t>(v.data, n);
    default: throw Error(where + " is not a numeric array");
  }
}

MatVar read_var(mat_t* mat, const std::string& name, const std::string& path) {
  MatVar v(Mat_VarRead(mat, name.c_str()));
  if (!v || !v->data) throw Error(path + ": cannot read the variable '" + name + "'");
  return v;
}

std::vector<std::string> variable_names(mat_t* mat) {
  std::vector<std::string> names;
  Mat_Rewind(mat);
  while (matvar_t* info = Mat_VarReadNextInfo(mat)) {
    if (info->name) names.emplace_back(info->name);
    Mat_VarFree(info);
  }
  Mat_Rewind(mat);
  return names;
}

/// Columns as vectors of one length, named.
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  std::size_t rows = 0;
};

Table matrix_table(mat_t* mat, const ReadOptions& o, const std::string& path) {
  const MatVar v = read_var(mat, o.mat_variable, path);
  const std::string where = path + ": variable '" + o.mat_variable + "'";
  if (v->rank != 2) throw Error(where + " must be a 2-D matrix");
  const std::size_t rows = v->dims[0], cols = v->dims[1];
  if (o.columns.size() != cols)
    throw Error(where + " has " + std::to_string(cols) + " columns; 'columns' names " +
                std::to_string(o.columns.size()));
  const auto all = numbers(*v, where);
  Table t;
  t.rows = rows;
  t.names = o.columns;
  for (std::size_t c = 0; c < cols; ++c)
    t.columns.emplace_back(all.begin() + static_cast<std::ptrdiff_t>(c * rows),
                           all.begin() + static_cast<std::ptrdiff_t>((c + 1) * rows));
  return t;
}

Table vector_table(mat_t* mat, const ReadOptions& o, const std::string& path) {
  Table t;
  for (const auto& name : variable_names(mat)) {
    const bool wanted = name == o.x_column || name == o.t_column || name == o.traj_column ||
                        (o.read_u && name == o.u_column) || (o.read_y && name == o.y_column);
    t.names.push_back(name);
    if (!wanted) {
      t.columns.emplace_back();
      continue;
    }
    const MatVar v = read_var(mat, name, path);
    const std::string where = path + ": variable '" + name + "'";
    if (v->rank != 2 || (v->dims[0] != 1 && v->dims[1] != 1))
      throw Error(where + " must be a vector (or give 'mat_variable' and 'columns' for a matrix)");
    t.columns.push_back(numbers(*v, where));
    if (t.rows == 0) t.rows = t.columns.back().size();
    if (t.columns.back().size() != t.rows)
      throw Error(where + " has " + std::to_string(t.columns.back().size()) + " values, the others " +
                  std::to_string(t.rows));
  }
  return t;
}

}  // namespace

Dataset read_mat(const std::string& path, const ReadOptions& o, ReadSummary& summary) {
  const Hdf5ErrorCapture hdf5_errors;  // (before the file: it also covers the close)
  MatFile mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  const auto corrupt = [&] {
    return Error(path + ": cannot read as a MATLAB v7.3 .mat file: HDF5 finds it corrupt or truncated");
  };
  if (hdf5_errors.failed()) throw corrupt();  // (libmatio returns a file whose variables cannot be read)
  if (!mat) throw Error(path + ": cannot open as a MATLAB .mat file");
  const Table t = o.mat_variable.empty() ? vector_table(mat.get(), o, path) : matrix_table(mat.get(), o, path);
  if (hdf5_errors.failed()) throw corrupt();
  const ColumnIndex idx = index_columns(t.names, o, path, "variable");
  auto col = [&](int i) -> const std::vector<double>* { return i < 0 ? nullptr : &t.columns[static_cast<std::size_t>(i)]; };
  const auto *x = col(idx.x), *tt = col(idx.t), *traj = col(idx.traj), *u = col(idx.u), *y = col(idx.y);
  Dataset d;
  RecordBuilder rb(d, path, o, idx.present(), summary, "row");
  for (std::size_t i = 0; i < t.rows; ++i) {
    Row r;
    r.line = i + 1;
    r.x = (*x)[i];
    if (tt) r.t = (*tt)[i];
    if (u) r.u = (*u)[i];
    if (y) r.y = (*y)[i];
    if (traj) r.id = (*traj)[i];  // (RecordBuilder checks it)
    rb.row(r);
  }
  rb.finish();
  return d;
}

}  // namespace vehs::io_detail
