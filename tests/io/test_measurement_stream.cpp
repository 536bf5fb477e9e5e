// read_measurements(std::istream&, name): the entry point the file readers go through and the
// fuzz targets (bench/fuzz/reader_target.cpp) call; the regressions of their findings.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <streambuf>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace fs = std::filesystem;

namespace {

/// A stream that cannot seek (a pipe): the readers size nothing by its length.
class PipeBuf : public std::streambuf {
 public:
  explicit PipeBuf(std::string bytes) : bytes_(std::move(bytes)) {
    setg(bytes_.data(), bytes_.data(), bytes_.data() + bytes_.size());
  }

 private:
  std::string bytes_;
};

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

vehs::Dataset ramp(std::size_t n) {
  vehs::Dataset d;
  vehs::Record r;
  r.id = 4;
  r.dt = 0.25;
  r.size = n;
  for (std::size_t i = 0; i < n; ++i) d.x.push_back(static_cast<double>(i % 1000) / 7.0);
  d.records.push_back(r);
  return d;
}

std::string error_of(const std::string& bytes, const std::string& name) {
  std::istringstream in(bytes);
  try {
    (void)vehs::read_measurements(in, name);
  } catch (const vehs::Error& e) {
    return e.what();
  }
  return "";
}

std::string npy(const std::string& header, const std::string& data = "") {
  std::string h = header;
  h.append((64 - (10 + h.size() + 1) % 64) % 64, ' ');
  h += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(h.size() & 0xff);
  out += static_cast<char>(h.size() >> 8);
  return out + h + data;
}

}  // namespace

TEST_CASE("a measurement stream reads as the file it holds (seekable or a pipe)", "[io][stream]") {
  // 300000 rows of CSV are over 4 MiB: lines cross the reader's chunks
  const auto d = ramp(300000);
  for (const char* ext : {".csv", ".npy"}) {
    CAPTURE(ext);
    const auto path = (fs::temp_directory_path() / (std::string("vehs_stream") + ext)).string();
    vehs::write_measurements(path, d, {});
    const std::string bytes = file_bytes(path);
    if (std::string(ext) == ".csv") CHECK(bytes.size() > (std::size_t{1} << 22));
    const auto from_file = vehs::read_measurements(path);
    std::istringstream seekable(bytes);
    PipeBuf pipe_buf(bytes);
    std::istream pipe(&pipe_buf);
    for (std::istream* in : {static_cast<std::istream*>(&seekable), &pipe}) {
      const auto back = vehs::read_measurements(*in, path);
      CHECK(back.x == d.x);
      CHECK(back.x == from_file.x);
      REQUIRE(back.records.size() == 1);
      CHECK(back.records[0].id == 4);
      CHECK(back.records[0].dt == Approx(0.25).epsilon(1e-12));
      CHECK(back.records[0].source == path);
    }
    fs::remove(path);
  }
  CHECK(error_of("t,x\n0,1\n", "a.mat").find("a.mat: .mat files are read from a path") == 0);
}

TEST_CASE("fuzz findings: .npy headers that looped or sized memory by a corrupt row count", "[io][stream]") {
  const auto start = std::chrono::steady_clock::now();
  // a field list without ']' and an entry without ')' sent the field loop back to the start of
  // the header for ever (fuzz_npy_reader timeout)
  CHECK(error_of(npy("{'shape': (3,), 'descr': [('x', '<f8' }"), "h.npy").find("h.npy: unsupported .npy header") == 0);
  CHECK(error_of(npy("{'shape': (3,), 'descr': [('x', '<f8'), ('t', '<f8' ], }"), "h.npy")
            .find("unsupported .npy header (field entry)") != std::string::npos);
  CHECK(error_of(npy("{'shape': (3,), 'descr':     "), "h.npy").find("unsupported .npy header (descr)") !=
        std::string::npos);
  CHECK(error_of(npy("{'descr': '<f8', 'shape': (3,), }"), "h.npy").empty() == false);  // no data: truncated
  CHECK(error_of(npy("{'descr': '<f16', 'shape': (3,), }"), "h.npy").find("field type <f16") != std::string::npos);
  // 10^15 rows claimed by a 24-byte file: an error before any allocation (was a reserve of 8 PB)
  const std::string small = npy("{'descr': [('t', '<f8'), ('x', '<f8')], 'fortran_order': False, 'shape': (1000000000000000,), }",
                                std::string(24, '\0'));
  CHECK(error_of(small, "big.npy").find("big.npy: truncated .npy data (expected 1000000000000000 rows of 16 bytes)") == 0);
  PipeBuf pipe_buf(small);
  std::istream pipe(&pipe_buf);
  CHECK_THROWS_WITH(vehs::read_measurements(pipe, "big.npy"), Catch::Contains("truncated .npy data"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}

TEST_CASE("a CSV header of 30000 names is checked for duplicates in linear time", "[io][stream]") {
  std::string header;
  for (int i = 0; i < 30000; ++i) header += "c" + std::to_string(i) + ",";
  const auto start = std::chrono::steady_clock::now();
  CHECK(error_of(header + "t,x,c17\n", "wide.csv").find("wide.csv: the column name 'c17' appears twice") == 0);
  CHECK(error_of(header + "t,x\n", "wide.csv").find("wide.csv: no usable data rows") == 0);
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}
