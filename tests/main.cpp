// The test runner. Every test process gets its own temporary folder (TMPDIR), so tests that
// use fixed names under std::filesystem::temp_directory_path() cannot collide when two suites
// run at once on one machine (several checkouts, or ctest -j); it is removed at exit.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

int main(int argc, char* argv[]) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("vehs-tests-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!ec) ::setenv("TMPDIR", dir.c_str(), 1);
  const int result = Catch::Session().run(argc, argv);
  if (!ec) fs::remove_all(dir, ec);
  return result;
}
