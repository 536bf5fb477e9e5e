#include "vehs/io/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vehs/core/error.hpp"
#include "vehs/io/output_transaction.hpp"
#include "vehs/io/path_text.hpp"

namespace vehs {

namespace {

// Writes the content into `file` (a temporary or staged file), removing it when writing fails;
// errors name `path`, the destination.
void write_content(const std::string& file, const std::string& path,
                   const std::function<void(std::ostream&)>& writer) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
  errno = 0;  // the failing write's error, when the stream fails
  try {
    writer(out);
  } catch (...) {
    out.close();
    std::remove(file.c_str());
    throw;
  }
  out.flush();
  if (!out) {
    const int err = errno;  // ENOSPC, EFBIG (a file size limit), EDQUOT, EIO
    out.close();
    std::remove(file.c_str());
    throw Error(path + ": write failed (" + (err ? std::string(std::strerror(err)) : std::string("disk full?")) + ")");
  }
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer) {
  check_path_text(path, "output file");
  if (OutputTransaction* t = OutputTransaction::active()) {  // committed with the run's other outputs
    write_content(t->stage(path), path, writer);
    return;
  }
  namespace fs = std::filesystem;
  check_output_path(path);
  const fs::path target(path);
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw Error(path + ": cannot create directory (" + ec.message() + ")");
  }
  static std::atomic<int> counter{0};
  const std::string tmp = (target.parent_path() / (".vehs-tmp." + std::to_string(::getpid()) + "." +
                                                   std::to_string(counter++))).string();
  const int slot = register_temporary(tmp, false);
  try {
    write_content(tmp, path, writer);
  } catch (...) {
    unregister_temporary(slot);
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    unregister_temporary(slot);
    throw Error(path + ": cannot move the finished output into place (" + why + ")");
  }
  unregister_temporary(slot);
}

void write_file_atomically(const std::string& path, const std::string& content) {
  write_file_atomically(path, [&](std::ostream& os) { os << content; });
}

void write_json_atomically(const std::string& path, const nlohmann::ordered_json& j) {
  write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace vehs
