// What the readers refused only in some formats, or not at all (an outside bad-input trial): record
// ids that are no integers in .mat files, ids beyond 2^53, .npy sub-array fields, a corrupt v7.3
// .mat file (HDF5's diagnostics), paths that are no regular files and paths with control characters.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "logger_files.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;

namespace {

std::string temp(const std::string& name) { return (fs::temp_directory_path() / name).string(); }

/// The error `read` throws, with what it printed on stderr meanwhile appended after " | stderr: ".
std::string error_of(const std::function<void()>& read) {
  const std::string log = temp("vehs_reader_checks_stderr.txt");
  std::fflush(stderr);
  const int saved = ::dup(2), fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ::dup2(fd, 2);
  ::close(fd);
  std::string message = "no error";
  try {
    read();
  } catch (const vehs::Error& e) {
    message = e.what();
  }
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  std::ifstream in(log);
  const std::string printed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return printed.empty() ? message : message + " | stderr: " + printed;
}

std::string read_error(const std::string& path) {
  return error_of([&] { (void)vehs::read_measurements(path); });
}

std::vector<double> sine(std::size_t n, double phase) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = std::sin(0.05 * static_cast<double>(i) + phase);
  return x;
}

vehs::Dataset records_with_id(long long id) {
  vehs::Dataset d;
  vehs::Record r;
  r.id = id;
  r.dt = 0.01;
  r.size = 100;
  d.x = sine(100, 0.0);
  d.records.push_back(r);
  return d;
}

}  // namespace

TEST_CASE(".mat record ids must be integers - as in CSV and .npy", "[io][reader_checks]") {
  // two records labelled 0.2 and 0.7 were read as one record 0
  const std::string m = temp("vehs_fractional_ids.mat");
  std::vector<double> traj(200, 0.2), t(200), x = sine(200, 0.0);
  for (std::size_t i = 0; i < 200; ++i) t[i] = 0.01 * static_cast<double>(i % 100), traj[i] = i < 100 ? 0.2 : 0.7;
  vehs::test::write_mat_v4(m, {{"traj", 200, 1, traj}, {"t", 200, 1, t}, {"x", 200, 1, x}});
  CHECK(read_error(m) == m + ": row 1: record id 0.2 is not an integer");
}

TEST_CASE("record ids up to 2^53 - 1 are read - larger ones are refused saying so", "[io][reader_checks]") {
  // ids from 2^53 - 4 up were refused as "not an integer"
  const long long big = (1LL << 53) - 4;
  for (const char* ext : {".csv", ".npy"}) {
    INFO(ext);
    const std::string p = temp(std::string("vehs_big_id") + ext);
    vehs::write_measurements(p, records_with_id(big), vehs::WriteColumns{});
    CHECK(vehs::read_measurements(p).records.at(0).id == big);
    vehs::write_measurements(p, records_with_id((1LL << 53) + 2), vehs::WriteColumns{});
    CHECK_THAT(read_error(p), Catch::StartsWith(p + ": ") && Catch::Contains(" is beyond the largest record id, "
                                                                             "2^53 - 1 = 9007199254740991"));
  }
  const std::string c = temp("vehs_big_id_text.csv");
  std::ofstream(c) << "traj,t,x\n9007199254740993,0,1\n9007199254740993,0.1,2\n";
  CHECK_THAT(read_error(c), Catch::StartsWith(c + ": line 2: record id '9007199254740993' is beyond"));
}

TEST_CASE(".npy structured fields of several values per row are refused by name", "[io][reader_checks]") {
  // dtype [('t', '<f8'), ('x', '<f8', (2,))] was read at the wrong stride, ending in a garbage record id
  const std::string p = temp("vehs_subarray.npy");
  std::string header = "{'descr': [('traj', '<i8'), ('t', '<f8'), ('x', '<f8', (2,))], 'fortran_order': False, "
                       "'shape': (3,), }";
  header.append(64 - (10 + header.size() + 1) % 64, ' ');
  header += '\n';
  std::ofstream f(p, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const char len[2] = {static_cast<char>(header.size() & 0xff), static_cast<char>(header.size() >> 8)};
  f.write(len, 2);
  f << header << std::string(3 * 32, '\0');
  f.close();
  CHECK(read_error(p) == p + ": field 'x' is a sub-array of shape (2,) (each field must hold one number per row: "
                             "one field per column, or a 2-D array with 'columns')");
}

TEST_CASE("a corrupt v7.3 .mat file is one line naming it - without HDF5's diagnostics", "[io][reader_checks]") {
  const std::string p = temp("vehs_corrupt73.mat");
  std::string head = "MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  5 10:00:00 2026 HDF5 schema 1.00 .";
  head.resize(116, ' ');
  head += std::string(8, '\0') + std::string("\x00\x02", 2) + "IM";
  head.resize(512, '\0');
  std::ofstream(p, std::ios::binary) << head << std::string(400, 'g');
  CHECK(read_error(p) == p + ": cannot read as a MATLAB v7.3 .mat file: HDF5 finds it corrupt or truncated");
}

TEST_CASE("a path that is no regular file is refused before it is opened", "[io][reader_checks]") {
  // a FIFO blocked identify-vehs and diagnose-vehs for ever
  const std::string fifo = temp("vehs_data_fifo.csv");
  std::remove(fifo.c_str());
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(read_error(fifo) == fifo + ": is a FIFO (named pipe); measurement files must be regular files");
  std::remove(fifo.c_str());
  CHECK(read_error("/dev/null") == "/dev/null: is a device; measurement files must be regular files");
  CHECK(read_error(fs::temp_directory_path().string()) ==
        fs::temp_directory_path().string() + ": is a directory; measurement files must be regular files");
}

TEST_CASE("a control character in a path is refused (a NUL cut it)", "[io][reader_checks]") {
  const std::string good = temp("vehs_nul.csv");
  vehs::write_measurements(good, records_with_id(1), vehs::WriteColumns{});
  CHECK_THAT(read_error(good + std::string("\0junk", 5)),
             Catch::Contains("'" + good + "\\x00junk' contains the control character 0x00 (NUL) at byte " +
                             std::to_string(good.size() + 1)));
  CHECK_THAT(read_error(good + "\n"), Catch::Contains("0x0a (line feed)"));
  const std::string npy = temp("vehs_nul.npy");
  std::remove(npy.c_str());
  CHECK_THAT(error_of([&] {
               vehs::write_measurements(npy + std::string("\0.csv", 5), records_with_id(1), vehs::WriteColumns{});
             }),
             Catch::StartsWith("output file: the path") && Catch::Contains("0x00 (NUL)"));
  CHECK_FALSE(fs::exists(npy));
  CHECK_THAT(error_of([&] { (void)vehs::model_from_config_value(std::string("m.json\x7f"), "cfg.json: 'model'"); }),
             Catch::StartsWith("cfg.json: 'model': the path 'm.json\\x7f' contains the control character 0x7f"));
}
