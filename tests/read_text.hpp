#pragma once
// A whole file as text (tests that read what the code or the tools wrote).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vehs_test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace vehs_test
