#pragma once
// The tool tests' shared pieces: a work folder in the build tree, and identify-vehs run in-process
// as a user runs it (argv, its stderr captured, stdout kept off the test's output).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "read_text.hpp"
#include "tools/tools.hpp"

namespace vehs_tool_test {

/// <build>/<name>, created.
inline std::filesystem::path work_dir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(VEHS_BINARY_DIR) / name;
  std::filesystem::create_directories(p);
  return p;
}

/// The whole text of a file ("" when it cannot be read).
using vehs_test::slurp;

/// identify-vehs with `args`; its exit status, stderr into `err` (when given).
inline int run_identify(const std::vector<std::string>& args, std::string* err = nullptr) {
  std::vector<std::string> a{"identify-vehs"};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  std::ostringstream e, o;
  auto* old_err = std::cerr.rdbuf(e.rdbuf());
  auto* old_out = std::cout.rdbuf(o.rdbuf());
  const int code = vehs::tools::identify_main(static_cast<int>(argv.size()), argv.data());
  std::cerr.rdbuf(old_err);
  std::cout.rdbuf(old_out);
  if (err) *err = e.str();
  return code;
}

}  // namespace vehs_tool_test
