// NumPy .npy: a 1-D structured array whose field names are the columns, or a 2-D C-order float
// array whose columns ReadOptions::columns names. Streamed in 4 MiB chunks; the header's row count
// is checked against the stream's length before anything is sized by it.
#include <algorithm>
#include <cmath>
#include <istream>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>

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
  const std::string type = t.substr(1);
  if (type != "f4" && type != "f8" && type != "i4" && type != "i8") unsupported(path, "field type " + t);
  f.kind = type[0];
  f.size = type[1] - '0';
}

std::vector<std::size_t> parse_shape(const std::string& header, const std::string& path) {
  const auto sh = header.find("'shape':");
  if (sh == std::string::npos) unsupported(path, "no shape");
  const auto lp = header.find('(', sh), rp = header.find(')', sh);
  if (lp == std::string::npos || rp == std::string::npos || rp < lp) unsupported(path, "shape");
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
  if (pos == std::string::npos) unsupported(path, "descr");
  if (header[pos] == '\'') {  // a plain dtype: one column named x, or a 2-D array with `columns`
    const auto q = header.find('\'', pos + 1);
    if (q == std::string::npos) unsupported(path, "descr");
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
  const auto close_list = header.find(']', pos);
  if (close_list == std::string::npos) unsupported(path, "descr list without ']'");
  std::size_t offset = 0;
  while (true) {  // ('name', '<f8') entries up to the list's end, each searched once
    const auto open = header.find('(', pos);
    if (open == std::string::npos || open > close_list) break;
    const auto close = header.find(')', open);
    if (close == std::string::npos || close > close_list) unsupported(path, "field entry");
    std::size_t q[4], from = open;
    for (auto& qi : q) {
      qi = header.find('\'', from);
      if (qi == std::string::npos || qi > close) unsupported(path, "field entry");
      from = qi + 1;
    }
    const auto q1 = q[0], q2 = q[1], q3 = q[2], q4 = q[3];
    NpyField f;
    f.name = header.substr(q1 + 1, q2 - q1 - 1);
    if (const auto after = header.find_first_not_of(", ", q4 + 1); after < close)  // ('x', '<f8', (2,))
      throw Error(path + ": field '" + f.name + "' is a sub-array of shape " + header.substr(after, close - after + 1) +
                  " (each field must hold one number per row: one field per column, or a 2-D array with 'columns')");
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

bool read_exactly(std::istream& in, char* dst, std::size_t n) {
  in.read(dst, static_cast<std::streamsize>(n));
  return static_cast<std::size_t>(in.gcount()) == n;
}

std::string read_header(std::istream& in, const std::string& path) {
  char magic[8];
  if (!read_exactly(in, magic, 8) || std::memcmp(magic, "\x93NUMPY", 6) != 0)
    throw Error(path + ": not a NumPy .npy file");
  std::size_t hlen = 0;
  unsigned char b[4] = {0, 0, 0, 0};
  if (!read_exactly(in, reinterpret_cast<char*>(b), magic[6] == 1 ? 2 : 4))
    throw Error(path + ": truncated .npy header");
  hlen = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::size_t>(b[3]) << 24);
  if (hlen > (std::size_t{1} << 20))  // numpy writes headers of < 10 kB; a length from a corrupt file
    throw Error(path + ": .npy header of " + std::to_string(hlen) + " bytes (corrupt file?)");  // is no allocation size
  std::string header(hlen, '\0');
  if (!read_exactly(in, header.data(), hlen)) throw Error(path + ": truncated .npy header");
  return header;
}

}  // namespace

Dataset read_npy(std::istream& in, const std::string& path, const ReadOptions& o, ReadSummary& summary) {
  const NpyLayout layout = parse_header(read_header(in, path), path, o);
  std::vector<std::string> names;
  std::size_t row_size = 0;
  for (const auto& f : layout.fields) {
    names.push_back(f.name);
    row_size = std::max(row_size, f.offset + static_cast<std::size_t>(f.size));
  }
  const ColumnIndex idx = index_columns(names, o, path, "field");
  auto field = [&](int i) -> const NpyField* { return i < 0 ? nullptr : &layout.fields[static_cast<std::size_t>(i)]; };
  const NpyField *fx = field(idx.x), *ft = field(idx.t), *ftraj = field(idx.traj), *fu = field(idx.u), *fy = field(idx.y);
  // the header's row count is checked against the bytes there are before it sizes anything
  const std::optional<std::size_t> left = bytes_left(in);
  const auto truncated = [&] {
    return Error(path + ": truncated .npy data (expected " + std::to_string(layout.rows) + " rows of " +
                 std::to_string(row_size) + " bytes)");
  };
  if (left && layout.rows > *left / row_size) throw truncated();
  const std::size_t reserve = left ? layout.rows : std::min<std::size_t>(layout.rows, kChunkBytes);
  Dataset d;
  d.x.reserve(reserve);
  if (fu) d.u.reserve(reserve);
  if (fy) d.y.reserve(reserve);
  // .npy rows are numbered from 1 in messages ("row 1" is the first)
  RecordBuilder rb(d, path, o, idx.present(), summary, "row");
  const std::size_t chunk_rows = std::max<std::size_t>(1, kChunkBytes / row_size);
  std::vector<char> buf(std::min(chunk_rows, layout.rows) * row_size);
  std::size_t row = 0;
  while (row < layout.rows) {
    const std::size_t want = std::min(chunk_rows, layout.rows - row);
    if (!read_exactly(in, buf.data(), want * row_size)) throw truncated();
    for (std::size_t k = 0; k < want; ++k, ++row) {
      const char* p = buf.data() + k * row_size;
      Row r;
      r.line = row + 1;
      r.x = field_value(p, *fx);
      if (ft) r.t = field_value(p, *ft);
      if (fu) r.u = field_value(p, *fu);
      if (fy) r.y = field_value(p, *fy);
      if (ftraj) r.id = field_value(p, *ftraj);  // (RecordBuilder checks it)
      rb.row(r);
    }
  }
  rb.finish();
  return d;
}

}  // namespace vehs::io_detail
