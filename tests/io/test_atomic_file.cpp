#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"

namespace fs = std::filesystem;

TEST_CASE("atomic writes leave either the whole file or nothing", "[io]") {
  const auto p = (fs::temp_directory_path() / "vehs_atomic" / "sub" / "f.txt").string();
  fs::remove_all(fs::temp_directory_path() / "vehs_atomic");
  vehs::write_file_atomically(p, "hello\n");
  std::ifstream in(p);
  std::string s;
  std::getline(in, s);
  CHECK(s == "hello");
  CHECK_THROWS(vehs::write_file_atomically(p, [](std::ostream& os) {
    os << "partial";
    throw vehs::Error("boom");
  }));
  std::ifstream again(p);
  std::getline(again, s);
  CHECK(s == "hello");  // the failed write did not touch the old file
  for (auto& e : fs::directory_iterator(fs::path(p).parent_path()))
    CHECK(e.path().filename() == "f.txt");  // no temporary left behind
}
