#pragma once
// Outputs written atomically: into a temporary file in the target's directory, then rename(2),
// so that a failed or interrupted run never leaves a partial file behind (the temporary is
// registered for the signal handler of output_transaction.hpp). Inside an OutputTransaction the
// file is staged instead and moved into place with the run's other outputs at commit. The path is
// checked first (check_output_path: never a directory, device, pipe or symbolic link).
#include <functional>
#include <iosfwd>
#include <string>

#include <nlohmann/json.hpp>

namespace vehs {

/// Writes `content` to `path` atomically; creates missing parent directories. Throws vehs::Error
/// naming the path when it cannot.
void write_file_atomically(const std::string& path, const std::string& content);
/// Same, with a writer streaming into the temporary file (large outputs).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& writer);
/// JSON with 2-space indentation, written atomically.
void write_json_atomically(const std::string& path, const nlohmann::ordered_json& j);

}  // namespace vehs
