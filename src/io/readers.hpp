#pragma once
// Internal: one reader per file format, each feeding io_detail::RecordBuilder.
#include <cstddef>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "record_builder.hpp"

#include "vehs/core/dataset.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::io_detail {

/// Bytes left in a seekable stream from its position; nullopt when unknown (a pipe).
std::optional<std::size_t> bytes_left(std::istream& in);

/// The chunk the stream readers read at once (a smaller file is read in one).
constexpr std::size_t kChunkBytes = std::size_t{1} << 22;

/// The format readers over a stream of a file's bytes; `name` names it in messages and records.
/// read_csv's `chunk_bytes` is the most it reads at once (the fuzz target varies it).
Dataset read_csv(std::istream& in, const std::string& name, const ReadOptions& o, ReadSummary& summary,
                 std::size_t chunk_bytes = kChunkBytes);
Dataset read_npy(std::istream& in, const std::string& name, const ReadOptions& o, ReadSummary& summary);
/// .mat files only from a path (libmatio reads files).
Dataset read_mat(const std::string& path, const ReadOptions& o, ReadSummary& summary);

/// The column roles of a file from its column names (a CSV header, a structured dtype, .mat
/// variables or ReadOptions::columns): index per role, −1 when absent. Throws vehs::Error naming
/// `path` for a duplicate name, a missing x or time column, or a missing required drive.
struct ColumnIndex {
  int t = -1, x = -1, traj = -1, u = -1, y = -1;
  Columns present() const { return Columns{t >= 0, traj >= 0, u >= 0, y >= 0}; }
};
ColumnIndex index_columns(const std::vector<std::string>& names, const ReadOptions& o, const std::string& path,
                          const char* kind);

}  // namespace vehs::io_detail
