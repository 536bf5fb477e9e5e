#include "tools/file_globs.hpp"

#include <glob.h>
#include <sys/stat.h>

#include <algorithm>

#include "vehs/core/error.hpp"

namespace vehs::tools {

bool has_glob_characters(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

std::vector<std::string> expand_file_glob(const std::string& pattern, const std::string& where) {
  struct stat st {};
  if (!has_glob_characters(pattern) || ::stat(pattern.c_str(), &st) == 0) return {pattern};
  glob_t g{};
  const int status = ::glob(pattern.c_str(), GLOB_NOSORT, nullptr, &g);
  std::vector<std::string> out;
  if (status == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  ::globfree(&g);
  if (status == GLOB_NOSPACE) throw Error(where + ": \"" + pattern + "\": out of memory while matching files");
  if (out.empty()) throw Error(where + ": \"" + pattern + "\" matches no file");
  std::sort(out.begin(), out.end());  // bytewise: glob's own order follows the locale
  return out;
}

std::vector<std::string> expand_file_globs(const std::vector<std::string>& paths, const std::string& where) {
  std::vector<std::string> out;
  for (const std::string& p : paths)
    for (std::string& m : expand_file_glob(p, where)) out.push_back(std::move(m));
  return out;
}

}  // namespace vehs::tools
