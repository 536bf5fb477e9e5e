#pragma once
// The text of a path read from a config, a model file or a caller: a control character in it
// (NUL 0x00, 0x01-0x1f, DEL 0x7f) is refused before the path is used. The operating system ends
// a path at its first NUL ("data.csv\u0000junk" would read data.csv, "sim.npy\u0000.csv" write
// CSV text into sim.npy); the others are editing or encoding accidents, not file names.
#include <string>

namespace vehs {

/// "" when `path` may name a file, else why not ("contains the control character 0x00 (NUL) at
/// byte 9").
std::string path_text_problem(const std::string& path);

/// `path` for messages: control characters shown as `\xNN`.
std::string escaped_path(const std::string& path);

/// Throws vehs::Error "<where>: <path_text_problem>" when `path` holds a control character.
void check_path_text(const std::string& path, const std::string& where);

}  // namespace vehs
