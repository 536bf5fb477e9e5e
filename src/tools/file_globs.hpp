#pragma once
// Shell-style patterns in a config's `data` ("../rig/run_*.csv"): expanded by POSIX glob(3),
// never by a shell, into the matching paths in byte order (the same order on every machine and
// locale). A name that is an existing file is taken as it is, even with `*`, `?` or `[` in it.
#include <string>
#include <vector>

namespace vehs::tools {

/// true when `text` holds a glob metacharacter (`*`, `?`, `[`).
bool has_glob_characters(const std::string& text);

/// The paths `pattern` names: itself when it has no metacharacter or names an existing file, else
/// its matches sorted bytewise. No match: vehs::Error "<where>: \"<pattern>\" matches no file".
std::vector<std::string> expand_file_glob(const std::string& pattern, const std::string& where);

/// Every entry of `paths` expanded in turn (the order of the list kept, each pattern's matches sorted).
std::vector<std::string> expand_file_globs(const std::vector<std::string>& paths, const std::string& where);

}  // namespace vehs::tools
