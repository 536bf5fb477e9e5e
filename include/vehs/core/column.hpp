#pragma once
// One column of a Dataset: either a std::vector<double> it owns, or a read-only view of a
// contiguous range of doubles owned by someone else (a NumPy array handed in from Python), which
// that owner keeps alive and unchanged while the view is used. Readers see the same interface
// either way (data, size, [], begin/end); the vector's mutating operations are for owning columns
// only and throw vehs::Error on a view, and own() copies a view into owned memory when a caller
// must modify it (copy-on-write, explicitly).
#include <cstddef>
#include <initializer_list>
#include <utility>
#include <vector>

#include "vehs/core/error.hpp"

namespace vehs {

class Column {
 public:
  using value_type = double;
  using iterator = std::vector<double>::iterator;
  using const_iterator = const double*;

  Column() = default;
  Column(std::vector<double> values) : owned_(std::move(values)) {}  // NOLINT: a vector is a column
  Column(std::initializer_list<double> values) : owned_(values) {}

  /// A view of `size` doubles at `data`: not copied, never written; the caller keeps them alive
  /// and unchanged for as long as this column (or a copy of it, which is the same view) is used.
  static Column view(const double* data, std::size_t size) {
    Column c;
    c.view_ = data;
    c.view_size_ = size;
    c.is_view_ = true;
    return c;
  }

  bool is_view() const { return is_view_; }
  /// Makes the column own its values (a view is copied once; an owning column is unchanged).
  void own() {
    if (!is_view_) return;
    owned_.assign(view_, view_ + view_size_);
    is_view_ = false;
    view_ = nullptr;
    view_size_ = 0;
  }

  // Reading: the same for owning columns and views.
  const double* data() const { return is_view_ ? view_ : owned_.data(); }
  std::size_t size() const { return is_view_ ? view_size_ : owned_.size(); }
  bool empty() const { return size() == 0; }
  const double& operator[](std::size_t i) const { return data()[i]; }
  const double* begin() const { return data(); }
  const double* end() const { return data() + size(); }
  const double& front() const { return data()[0]; }
  const double& back() const { return data()[size() - 1]; }

  // Writing: owning columns only (a view throws vehs::Error; call own() first to copy it).
  std::vector<double>& values() {
    if (is_view_) throw_view();
    return owned_;
  }
  double* data() { return values().data(); }
  double& operator[](std::size_t i) { return values()[i]; }
  iterator begin() { return values().begin(); }
  iterator end() { return values().end(); }
  double& back() { return values().back(); }
  std::size_t capacity() const { return is_view_ ? view_size_ : owned_.capacity(); }
  void push_back(double v) { values().push_back(v); }
  void reserve(std::size_t n) { values().reserve(n); }
  void resize(std::size_t n) { values().resize(n); }
  void resize(std::size_t n, double v) { values().resize(n, v); }
  void assign(std::size_t n, double v) { values().assign(n, v); }
  template <class It>
  void assign(It first, It last) {
    values().assign(first, last);
  }
  template <class It>
  iterator insert(iterator pos, It first, It last) {
    return values().insert(pos, first, last);
  }
  void shrink_to_fit() { values().shrink_to_fit(); }
  /// Empties the column (a view is dropped, its memory untouched).
  void clear() {
    *this = Column();
  }

  friend bool operator==(const Column& a, const Column& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!(a[i] == b[i])) return false;
    return true;
  }
  friend bool operator!=(const Column& a, const Column& b) { return !(a == b); }

 private:
  [[noreturn]] static void throw_view() {
    throw Error("a data column that views caller memory (a NumPy array) is read-only: it must be copied "
                "(Column::own) before it is modified");
  }
  std::vector<double> owned_;
  const double* view_ = nullptr;
  std::size_t view_size_ = 0;
  bool is_view_ = false;
};

}  // namespace vehs
