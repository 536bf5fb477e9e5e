#include "commit_journal.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vehs/core/error.hpp"

namespace vehs::journal {

namespace {

namespace fs = std::filesystem;

std::string errno_text() { return std::strerror(errno); }

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

bool is_staging_folder(const std::string& path) {
  return starts_with(fs::path(path).filename().string(), kStagingPrefix);
}

/// The process id written as `digits`, or 0.
long parse_pid(const std::string& digits) {
  if (digits.empty() || digits.size() > 9) return 0;
  for (const char c : digits)
    if (c < '0' || c > '9') return 0;
  return std::stol(digits);
}

bool process_gone(long pid) { return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

/// Whether `path` is one of `own` (compared as files: a folder reached through a link is the same).
bool is_own(const std::string& path, const std::vector<std::string>& own) {
  struct stat st {}, other {};
  if (::stat(path.c_str(), &st) != 0) return false;
  for (const auto& o : own)
    if (::stat(o.c_str(), &other) == 0 && other.st_dev == st.st_dev && other.st_ino == st.st_ino) return true;
  return false;
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

std::string read_small(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Unlinks every file of a staging folder, then the folder.
void clear_staging_folder(const std::string& folder) {
  if (!is_staging_folder(folder)) return;  // never anything else, whatever a journal says
  if (DIR* d = ::opendir(folder.c_str())) {
    std::vector<std::string> names;
    while (const dirent* e = ::readdir(d)) {
      const std::string n = e->d_name;
      if (n != "." && n != "..") names.push_back(n);
    }
    ::closedir(d);
    for (const auto& n : names) ::unlink((fs::path(folder) / n).c_str());
  }
  ::rmdir(folder.c_str());
}

struct Journal {
  std::vector<Move> moves;
  std::vector<std::string> folders;
};

/// The journal of the stale staging folder: its own or the one its pointer names; false when
/// there is none (the run never reached its commit point).
bool read_journal(const std::string& staging, Journal& out) {
  std::string path = (fs::path(staging) / kJournal).string();
  if (!exists(path)) {
    const std::string pointer = read_small((fs::path(staging) / kPointer).string());
    try {
      path = nlohmann::json::parse(pointer).at("journal").get<std::string>();
    } catch (const std::exception&) {
      return false;
    }
  }
  const std::string text = read_small(path);
  try {
    const auto j = nlohmann::json::parse(text);
    for (const auto& m : j.at("moves")) out.moves.push_back({m.at(0).get<std::string>(), m.at(1).get<std::string>()});
    for (const auto& f : j.at("folders")) out.folders.push_back(f.get<std::string>());
  } catch (const std::exception&) {
    return false;  // written by temporary + rename: a journal is whole or absent
  }
  return true;
}

void roll_forward(const std::string& staging, const Journal& j) {
  for (const auto& m : j.moves) {
    if (!is_staging_folder(fs::path(m.staged).parent_path().string()) || !exists(m.staged)) continue;
    if (::rename(m.staged.c_str(), m.destination.c_str()) != 0 && errno != ENOENT)
      throw Error(m.destination + ": cannot complete the outputs of an interrupted run (" + errno_text() +
                  "); they are in " + staging);
  }
  if (!j.folders.empty()) ::unlink((fs::path(j.folders.front()) / kJournal).c_str());  // done: commit over
  for (const auto& f : j.folders) clear_staging_folder(f);
  clear_staging_folder(staging);
}

void roll_back(const std::string& staging) {
  std::vector<std::string> created;
  try {
    for (const auto& f : nlohmann::json::parse(read_small((fs::path(staging) / kCreated).string())))
      created.push_back(f.get<std::string>());
  } catch (const std::exception&) {
  }
  clear_staging_folder(staging);
  for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());  // when empty
}

void recover_one(const std::string& staging, long pid, const char* program) {
  const int fd = ::open(staging.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;  // gone meanwhile (another run repaired it) or not a folder
  while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || st.st_nlink == 0) {  // removed by the run that held the lock
    ::close(fd);
    return;
  }
  Journal j;
  const bool committed = read_journal(staging, j);
  try {
    committed ? roll_forward(staging, j) : roll_back(staging);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  std::fprintf(stderr, "%s: %s: %s of an interrupted run (process %ld)\n", program, staging.c_str(),
               committed ? "completed the commit" : "removed the unfinished outputs", pid);
}

}  // namespace

std::string journal_text(const std::vector<Move>& moves, const std::vector<std::string>& folders) {
  nlohmann::json j;
  j["moves"] = nlohmann::json::array();
  for (const auto& m : moves) j["moves"].push_back({m.staged, m.destination});
  j["folders"] = folders;
  return j.dump() + "\n";
}

std::string pointer_text(const std::string& journal_path) {
  return nlohmann::json{{"journal", journal_path}}.dump() + "\n";
}

std::string created_text(const std::vector<std::string>& folders) { return nlohmann::json(folders).dump() + "\n"; }

void write_synced(const std::string& path, const std::string& content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) throw Error(path + ": cannot write the commit journal (" + errno_text() + ")");
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = n < 0 ? errno_text() : "nothing written";
      ::close(fd);
      ::unlink(path.c_str());
      throw Error(path + ": cannot write the commit journal (" + why + ")");
    }
    done += static_cast<std::size_t>(n);
  }
  const bool synced = ::fsync(fd) == 0;
  const std::string why = synced ? "" : errno_text();
  ::close(fd);
  if (!synced) {
    ::unlink(path.c_str());
    throw Error(path + ": cannot write the commit journal (" + why + ")");
  }
}

void sync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const std::string why = errno_text();
    if (fd >= 0) ::close(fd);
    throw Error(path + ": cannot flush to disk (" + why + ")");
  }
  ::close(fd);
}

void recover_stale_staging(const std::string& dir, const std::vector<std::string>& own, const char* program) {
  const std::string folder = fs::absolute(dir.empty() ? "." : dir).lexically_normal().string();
  std::vector<std::string> names;
  if (DIR* d = ::opendir(folder.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string n = e->d_name;
      if (starts_with(n, kStagingPrefix) || starts_with(n, ".vehs-tmp.")) names.push_back(n);
    }
    ::closedir(d);
  }
  for (const auto& n : names) {
    const std::string path = (fs::path(folder) / n).string();
    const bool staging = starts_with(n, kStagingPrefix);
    const std::string rest = n.substr(staging ? std::strlen(kStagingPrefix) : std::strlen(".vehs-tmp."));
    const long pid = parse_pid(staging ? rest : rest.substr(0, rest.find('.')));
    if (pid <= 0) continue;
    const bool mine = pid == static_cast<long>(::getpid());
    if (mine ? is_own(path, own) : !process_gone(pid)) continue;
    if (staging) {
      recover_one(path, pid, program);
    } else {
      struct stat st {};
      if (::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && !mine && ::unlink(path.c_str()) == 0)
        std::fprintf(stderr, "%s: %s: removed the temporary file of an interrupted run (process %ld)\n", program,
                     path.c_str(), pid);
    }
  }
}

}  // namespace vehs::journal
