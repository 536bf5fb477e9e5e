// NumPy .npy: a 1-D structured array whose field names are the columns, or a 2-D C-order float
// array whose columns ReadOptions::columns names. Streamed in 4 MiB chunks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "readers.hpp"
#include "vehs/core/error.hpp"

namespace vehs::io_detail {

namespace {

struct NpyField {
  std::string name;
  char kind = 'f';  // 'f' float, 'i' signed int
  int size = 8;
  std::size_t offset = 0;
};

struct NpyLayout {
  std::vector<NpyField> fields;
  std::size_t rows = 0;
};

[[noreturn]] void unsupported(const std::string& path, const std::string& m) {
  throw Error(path + ": unsupported .npy header (" + m + "); expected a 1-D structured array with fields like "
              "[('traj','<i8'),('t','<f8'),('x','<f8')], or a 2-D float array with 'columns' naming its columns");
}

void parse_type(const std::string& t, NpyField& f, const std::string& path) {
  if (t.size() < 3 || (t[0] != '<' && t[0] != '|' && t[0] != '=')) unsupported(path, "only little-endian");
  f.kind = t[1];
  f.size = std::atoi(t.c_str() + 2);
  if (!((f.kind == 'f' && (f.size == 4 || f.size == 8)) || (f.kind == 'i' && (f.size == 4 || f.size == 8))))
    unsupported(path, "field type " + t);
}

std::vector<std::size_t> parse_shape(const std::string& header, const std::string& path) {
  const auto sh = header.find("'shape':");
  if (sh == std::string::npos) unsupported(path, "no shape");
  const auto lp = header.find('(', sh), rp = header.find(')', sh);
  if (lp == std::string::npos || rp == std::string::npos) unsupported(path, "shape");
  std::vector<std::size_t> shape;
  const std::string inner = header.substr(lp + 1, rp - lp - 1);
  const char* p = inner.c_str();
  while (*p) {
    while (*p == ' ' || *p == ',') ++p;
    if (!*p) break;
    char* end = nullptr;
    shape.push_back(std::strtoull(p, &end, 10));
    if (end == p) unsupported(path, "shape");
    p = end;
  }
  return shape;
}

NpyLayout parse_header(const std::string& header, const std::string& path, const ReadOptions& o) {
  if (header.find("'fortran_order': True") != std::string::npos) unsupported(path, "Fortran order");
  const auto shape = parse_shape(header, path);
  const auto ds = header.find("'descr':");
  if (ds == std::string::npos) unsupported(path, "no descr");
  NpyLayout l;
  std::size_t pos = header.find_first_not_of(' ', ds + 8);
  if (header[pos] == '\'') {  // a plain dtype: one column named x, or a 2-D array with `columns`
    const auto q = header.find('\'', pos + 1);
    NpyField f;
    parse_type(header.substr(pos + 1, q - pos - 1), f, path);
    if (shape.size() == 1) {
      f.name = o.columns.empty() ? "x" : o.columns.front();
      l.fields.push_back(f);
    } else if (shape.size() == 2) {
      if (o.columns.size() != shape[1])
        throw Error(path + ": a 2-D array of " + std::to_string(shape[1]) + " columns needs 'columns' with " +
                    std::to_string(shape[1]) + " names (it has " + std::to_string(o.columns.size()) + ")");
      for (std::size_t c = 0; c < shape[1]; ++c) {
        NpyField g = f;
        g.name = o.columns[c];
        g.offset = c * static_cast<std::size_t>(f.size);
        l.fields.push_back(g);
      }
    } else {
      unsupported(path, "shape must be 1-D or 2-D");
    }
    l.rows = shape.empty() ? 0 : shape[0];
    return l;
  }
  if (shape.size() != 1) unsupported(path, "a structured array must be 1-D");
  if (header[pos] != '[') unsupported(path, "descr");
  std::size_t offset = 0;
  while (true) {
    const auto open = header.find('(', pos);
    const auto close_list = header.find(']', pos);
    if (open == std::string::npos || open > close_list) break;
    const auto q1 = header.find('\'', open), q2 = header.find('\'', q1 + 1);
    const auto q3 = header.find('\'', q2 + 1), q4 = header.find('\'', q3 + 1);
    const auto close = header.find(')', open);
    if (q4 == std::string::npos || q4 > close) unsupported(path, "field entry");
    NpyField f;
    f.name = header.substr(q1 + 1, q2 - q1 - 1);
    parse_type(header.substr(q3 + 1, q4 - q3 - 1), f, path);
    f.offset = offset;
    offset += static_cast<std::size_t>(f.size);
    l.fields.push_back(f);
    pos = close + 1;
  }
  if (l.fields.empty()) unsupported(path, "no fields");
  l.rows = shape[0];
  return l;
}

double field_value(const char* row, const NpyField& f) {
  if (f.kind == 'f') {
    if (f.size == 8) {
      double v;
      std::memcpy(&v, row + f.offset, 8);
      return v;
    }
    float v;
    std::memcpy(&v, row + f.offset, 4);
    return v;
  }
  if (f.size == 8) {
    long long v;
    std::memcpy(&v, row + f.offset, 8);
    return static_cast<double>(v);
  }
  int v;
  std::memcpy(&v, row + f.offset, 4);
  return v;
}

std::string read_header(std::FILE* f, const std::string& path) {
  char magic[8];
  if (std::fread(magic, 1, 8, f) != 8 || std::memcmp(magic, "\x93NUMPY", 6) != 0)
    throw Error(path + ": not a NumPy .npy file");
  std::size_t hlen = 0;
  if (magic[6] == 1) {
    unsigned char b[2];
    if (std::fread(b, 1, 2, f) != 2) throw Error(path + ": truncated .npy header");
    hlen = b[0] | (b[1] << 8);
  } else {
    unsigned char b[4];
    if (std::fread(b, 1, 4, f) != 4) throw Error(path + ": truncated .npy header");
    hlen = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::size_t>(b[3]) << 24);
  }
  if (hlen > (std::size_t{1} << 20))  // numpy writes headers of < 10 kB; a length from a corrupt file
    throw Error(path + ": .npy header of " + std::to_string(hlen) + " bytes (corrupt file?)");  // is no allocation size
  std::string header(hlen, '\0');
  if (std::fread(header.data(), 1, hlen, f) != hlen) throw Error(path + ": truncated .npy header");
  return header;
}

}  // namespace

Dataset read_npy(const std::string& path, const ReadOptions& o, ReadSummary& summary) {
  const File file = open_measurement_file(path);
  const NpyLayout layout = parse_header(read_header(file.get(), path), path, o);
  std::vector<std::string> names;
  std::size_t row_size = 0;
  for (const auto& f : layout.fields) {
    names.push_back(f.name);
    row_size = std::max(row_size, f.offset + static_cast<std::size_t>(f.size));
  }
  const ColumnIndex idx = index_columns(names, o, path, "field");
  auto field = [&](int i) -> const NpyField* { return i < 0 ? nullptr : &layout.fields[static_cast<std::size_t>(i)]; };
  const NpyField *fx = field(idx.x), *ft = field(idx.t), *ftraj = field(idx.traj), *fu = field(idx.u), *fy = field(idx.y);
  Dataset d;
  d.x.reserve(layout.rows);
  if (fu) d.u.reserve(layout.rows);
  if (fy) d.y.reserve(layout.rows);
  // .npy rows are numbered from 1 in messages ("row 1" is the first)
  RecordBuilder rb(d, path, o, idx.present(), summary, "row");
  const std::size_t chunk_rows = std::max<std::size_t>(1, (1u << 22) / row_size);
  std::vector<char> buf(chunk_rows * row_size);
  std::size_t row = 0;
  while (row < layout.rows) {
    const std::size_t want = std::min(chunk_rows, layout.rows - row);
    if (std::fread(buf.data(), row_size, want, file.get()) != want)
      throw Error(path + ": truncated .npy data (expected " + std::to_string(layout.rows) + " rows)");
    for (std::size_t k = 0; k < want; ++k, ++row) {
      const char* p = buf.data() + k * row_size;
      Row r;
      r.line = row + 1;
      r.x = field_value(p, *fx);
      if (ft) r.t = field_value(p, *ft);
      if (fu) r.u = field_value(p, *fu);
      if (fy) r.y = field_value(p, *fy);
      if (ftraj) {
        const double id = field_value(p, *ftraj);
        if (id != std::floor(id) || !(std::abs(id) < 9e15))  // (a larger id would overflow the conversion)
          throw Error(path + ": row " + std::to_string(row) + ": record id " + std::to_string(id) +
                      " is not an integer below 9e15");
        r.id = static_cast<long long>(id);
      }
      rb.row(r);
    }
  }
  rb.finish();
  return d;
}

}  // namespace vehs::io_detail
