#pragma once
// Reading JSON (model files, configs, statistics, --set values) with one-line errors naming the
// file, and short excerpts of JSON values for error messages. Bad input never crashes the reader:
// nesting is capped before parsing (a value nested 100,000 deep would otherwise overflow the stack
// wherever it is printed or copied), content after the document is rejected, a path that is a
// directory is refused, and a pipe is read (process substitution) but never waited for when it has
// no writer; at most kMaxJsonBytes are read (/dev/zero ends with an error, not a hang).
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace vehs {

/// Deepest nesting of arrays and objects accepted in any JSON input (configs and model files
/// nest fewer than 10 levels).
inline constexpr int kMaxJsonDepth = 64;
/// Largest JSON input read (a device such as /dev/zero would otherwise be read for ever).
inline constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;

/// The JSON value in `path`. Throws vehs::Error "<path>: cannot open <what> (<reason>)",
/// "<path>: is a directory, not a <what>", "<path>: not valid JSON (<parser message>)" or
/// "<path>: JSON nested deeper than 64 levels (line L)".
nlohmann::json read_json_file(const std::string& path, const std::string& what);

/// Parses `text` (one JSON document, nothing after it, nesting capped); errors start with `where`.
nlohmann::json parse_json_text(const std::string& text, const std::string& where);
/// The checks parse_json_text makes before parsing (nesting, NUL bytes), for callers that parse
/// into another JSON type (nlohmann::ordered_json).
void check_json_text(const std::string& text, const std::string& where);
/// The bytes of `path` (at most kMaxJsonBytes; a directory is refused, a pipe without a writer
/// read as empty); errors name the file and `what` it should be.
std::string read_text_file(const std::string& path, const std::string& what);

/// A one-line excerpt of `v` of at most about `max_chars` characters for error messages
/// ("[1, 2, ...]", "{\"a\": ...}"); never recurses deeper than the characters it prints.
std::string json_excerpt(const nlohmann::json& v, std::size_t max_chars = 40);

}  // namespace vehs
