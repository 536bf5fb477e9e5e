#include "vehs/io/output_transaction.hpp"

#include <climits>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "commit_journal.hpp"
#include "vehs/core/error.hpp"

namespace vehs {

namespace fs = std::filesystem;

// ---- temporaries removed by the signal handler ------------------------------------------------
// Fixed storage (no allocation in the handler): a slot is free (0), being filled (1), a file (2)
// or a folder (3). Folders are removed after files, deepest first (repeated passes).
namespace {

constexpr int kSlots = 4096;
constexpr std::size_t kPathBytes = PATH_MAX;
struct Slot {
  std::atomic<int> state;
  char path[kPathBytes];
};
Slot g_slots[kSlots];
std::atomic<bool> g_committing{false};
std::atomic<int> g_deferred_signal{0};
std::atomic<pid_t> g_child{0};
const char* g_program = "vehs";

void remove_temporaries() noexcept {
  for (auto& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  for (int pass = 0; pass < 32; ++pass) {
    bool removed = false;
    for (int i = kSlots - 1; i >= 0; --i)
      if (g_slots[i].state.load() == 3 && ::rmdir(g_slots[i].path) == 0) {
        g_slots[i].state.store(0);
        removed = true;
      }
    if (!removed) break;
  }
}

void write_stderr(const char* s) noexcept {
  const ssize_t ignored = ::write(STDERR_FILENO, s, std::strlen(s));
  (void)ignored;
}

[[noreturn]] void exit_on_signal(int sig, const char* what) noexcept {
  write_stderr(g_program);
  write_stderr(what);
  ::_exit(128 + sig);
}

extern "C" void on_signal(int sig) {
  if (g_committing.load()) {  // the outputs are being moved into place: finish, then exit
    g_deferred_signal.store(sig);
    return;
  }
  if (const pid_t child = g_child.exchange(0); child > 0) {  // gnuplot: stop it before its files go
    ::kill(child, SIGKILL);
    while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
    }
  }
  remove_temporaries();
  exit_on_signal(sig, ": interrupted; no outputs written, temporary files removed\n");
}

std::string errno_text() { return std::strerror(errno); }

}  // namespace

int register_temporary(const std::string& path, bool directory) {
  const std::string abs = fs::absolute(path).lexically_normal().string();
  if (abs.size() >= kPathBytes) throw Error(path + ": path longer than " + std::to_string(kPathBytes - 1) + " bytes");
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, abs.c_str(), abs.size() + 1);
      g_slots[i].state.store(directory ? 3 : 2);
      return i;
    }
  }
  throw Error(path + ": more than " + std::to_string(kSlots) + " output files in one run");
}

void unregister_temporary(int slot) noexcept {
  if (slot >= 0 && slot < kSlots) g_slots[slot].state.store(0);
}

void register_child(pid_t pid) noexcept { g_child.store(pid); }
void unregister_child() noexcept { g_child.store(0); }

void install_signal_cleanup(const char* program) {
  g_program = program;
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

// ---- output checks ------------------------------------------------------------------------------

void check_output_path(const std::string& path) {
  if (path.empty()) throw Error("an output path is empty");
  const fs::path p(path);
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw Error(path + ": an output must name a file, not a folder");
  if (name.rfind(".vehs-", 0) == 0)
    throw Error(path + ": names starting with .vehs- are reserved for the tools' staging and temporary files");
  if (name.size() > NAME_MAX)
    throw Error(path + ": file name of " + std::to_string(name.size()) + " bytes is longer than the " +
                std::to_string(NAME_MAX) + " the file system allows");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return;  // does not exist yet
  if (S_ISLNK(st.st_mode))
    throw Error(path + ": is a symbolic link; an output is never written over a link (remove it or name its target)");
  if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, not an output file");
  if (!S_ISREG(st.st_mode))
    throw Error(path + ": is a device, pipe or socket, not an output file (it would be replaced)");
}

// ---- the transaction ---------------------------------------------------------------------------

namespace {
OutputTransaction* g_active = nullptr;
std::mutex g_mutex;

std::string canonical_of(const std::string& path) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(fs::absolute(path), ec);
  return ec ? fs::absolute(path).lexically_normal().string() : c.string();
}

std::string folder_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

std::string absolute_of(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

// The test-only fault hook of commit(): VEHS_TEST_KILL_AT_RENAME=k kills the process with SIGKILL
// just before the k-th rename of the commit.
long g_renames = 0, g_kill_at = 0;

void start_counting_renames() {
  const char* v = std::getenv("VEHS_TEST_KILL_AT_RENAME");
  g_kill_at = v ? std::atol(v) : 0L;
  g_renames = 0;
}

int counted_rename(const std::string& from, const std::string& to) {
  if (++g_renames == g_kill_at) ::raise(SIGKILL);
  return ::rename(from.c_str(), to.c_str());
}
}  // namespace

OutputTransaction::OutputTransaction() {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_active) throw Error("internal: an output transaction is already open");
  g_active = this;
}

OutputTransaction::~OutputTransaction() {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (!committed_) rollback();
  g_active = nullptr;
}

OutputTransaction* OutputTransaction::active() { return g_active; }

void OutputTransaction::protect(const std::string& path, const std::string& what) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::lock_guard<std::mutex> lock(g_mutex);
  inputs_.push_back({{st.st_dev, st.st_ino}, path, what});
}

void OutputTransaction::check_output(const std::string& path) const {
  check_output_path(path);
  recover(folder_of(path));
  const std::string canonical = canonical_of(path);
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  for (const auto& in : inputs_)
    if (exists && in.id.dev == st.st_dev && in.id.ino == st.st_ino)
      throw Error(path + ": this output is the " + in.what + " " + in.path + " (it would be overwritten)");
  for (const auto& s : staged_) {
    struct stat other {};
    if (s.canonical == canonical ||
        (exists && ::stat(s.destination.c_str(), &other) == 0 && other.st_dev == st.st_dev && other.st_ino == st.st_ino))
      throw Error(path + ": written twice by this run (also as " + s.destination + "); give the outputs different names");
  }
}

void OutputTransaction::make_directories(const std::string& dir) {
  std::vector<fs::path> missing;
  for (fs::path p = fs::absolute(dir).lexically_normal(); !p.empty(); p = p.parent_path()) {
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) throw Error(dir + ": cannot create the output folder (" + p.string() + " is a file)");
      break;
    }
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST)
      throw Error(dir + ": cannot create the output folder (" + errno_text() + ")");
    created_dirs_.emplace_back(it->string(), register_temporary(it->string(), true));
  }
}

void OutputTransaction::recover(const std::string& dir) const {
  const std::string key = absolute_of(dir);
  if (std::find(recovered_.begin(), recovered_.end(), key) != recovered_.end()) return;
  journal::recover_stale_staging(key, staging_abs_, g_program);
  recovered_.push_back(key);
}

void recover_stale_outputs(const std::string& dir) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_active)
    g_active->recover(dir);
  else
    journal::recover_stale_staging(dir, {}, g_program);
}

std::string OutputTransaction::staging_directory(const std::string& dir) {
  const std::string key = absolute_of(dir);
  for (std::size_t i = 0; i < staging_for_.size(); ++i)
    if (staging_for_[i] == key) return staging_dirs_[i].first;
  recover(dir);
  make_directories(dir);
  const std::string sdir = (fs::path(dir) / (journal::kStagingPrefix + std::to_string(::getpid()))).string();
  if (::mkdir(sdir.c_str(), 0700) != 0 && errno != EEXIST) {
    const std::string why = errno == EACCES || errno == EROFS ? "the folder is not writable" : errno_text();
    throw Error(dir + ": cannot write outputs here (" + why + ")");
  }
  staging_dirs_.emplace_back(sdir, register_temporary(sdir, true));
  staging_for_.push_back(key);
  staging_abs_.push_back(absolute_of(sdir));
  // the folders this run created on the way: a later run removes them with a staging folder it
  // rolls back (when they are empty)
  std::vector<std::string> created;
  for (const auto& d : created_dirs_)
    if (key == d.first || key.rfind(d.first + "/", 0) == 0) created.push_back(d.first);
  if (!created.empty()) {
    const std::string list = (fs::path(sdir) / journal::kCreated).string();
    records_.emplace_back(list, register_temporary(list, false));
    journal::write_synced(list, journal::created_text(created));
  }
  return sdir;
}

void OutputTransaction::lock_output(const std::string& destination) {
  const std::string path = destination + ".lock";
  {
    std::lock_guard<std::mutex> lock(g_mutex);
    for (const auto& f : lock_files_)
      if (f.first == path) return;  // held already (a second flock of this process would wait for ever)
    recover(folder_of(destination));
    make_directories(folder_of(destination));
  }
  for (;;) {  // the lock file is removed by its holder: lock the file the name still names
    const int fd = ::open(path.c_str(), O_RDONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);  // (other users too)
    if (fd < 0) throw Error(path + ": cannot create the lock file (" + errno_text() + ")");
    while (::flock(fd, LOCK_EX) != 0)
      if (errno != EINTR) {
        const std::string why = errno_text();
        ::close(fd);
        throw Error(path + ": cannot lock (" + why + ")");
      }
    struct stat held {}, named {};
    if (::fstat(fd, &held) == 0 && ::lstat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      std::lock_guard<std::mutex> lock(g_mutex);
      lock_fds_.push_back(fd);
      lock_files_.emplace_back(path, register_temporary(path, false));
      return;
    }
    ::close(fd);
  }
}

std::string OutputTransaction::stage(const std::string& destination) {
  std::lock_guard<std::mutex> lock(g_mutex);
  check_output(destination);
  const std::string staged =
      (fs::path(staging_directory(folder_of(destination))) / fs::path(destination).filename()).string();
  staged_.push_back({staged, destination, canonical_of(destination), register_temporary(staged, false)});
  return staged;
}

void OutputTransaction::adopt(const std::string& destination) {
  std::lock_guard<std::mutex> lock(g_mutex);
  check_output(destination);
  const std::string staged =
      (fs::path(staging_directory(folder_of(destination))) / fs::path(destination).filename()).string();
  staged_.push_back({staged, destination, canonical_of(destination), register_temporary(staged, false)});
}

std::string OutputTransaction::current_path(const std::string& destination) const {
  std::lock_guard<std::mutex> lock(g_mutex);
  const std::string canonical = canonical_of(destination);
  for (auto it = staged_.rbegin(); it != staged_.rend(); ++it)
    if (it->canonical == canonical && it->slot >= 0) return it->staged;
  return destination;
}

std::string current_output_path(const std::string& destination) {
  const OutputTransaction* t = OutputTransaction::active();
  return t ? t->current_path(destination) : destination;
}

void OutputTransaction::commit() {
  std::lock_guard<std::mutex> lock(g_mutex);
  // inputs read after an output was staged are protected too: check everything before moving
  for (const auto& s : staged_) {
    check_output_path(s.destination);
    struct stat st {};
    if (::stat(s.destination.c_str(), &st) == 0)
      for (const auto& in : inputs_)
        if (in.id.dev == st.st_dev && in.id.ino == st.st_ino)
          throw Error(s.destination + ": this output is the " + in.what + " " + in.path + " (it would be overwritten)");
  }
  g_committing.store(true);
  start_counting_renames();
  try {
    if (!staged_.empty()) write_journal();
  } catch (...) {
    g_committing.store(false);
    throw;  // nothing moved: the destructor removes the staged files
  }
  move_into_place();
  finish();
  committed_ = true;
  g_committing.store(false);
  if (const int sig = g_deferred_signal.load())
    exit_on_signal(sig, ": interrupted after all outputs were written\n");
}

// The commit point: pointers in every staging folder but the first, then the master journal in
// the first (temporary, fsync, rename). The staged files are flushed to disk before it.
void OutputTransaction::write_journal() {
  std::vector<journal::Move> moves;
  for (const auto& s : staged_) {
    journal::sync_path(s.staged);
    moves.push_back({absolute_of(s.staged), absolute_of(s.destination)});
  }
  const std::string master = staging_abs_.front();
  const std::string path = (fs::path(master) / journal::kJournal).string();
  for (std::size_t i = 1; i < staging_abs_.size(); ++i) {
    const std::string pointer = (fs::path(staging_abs_[i]) / journal::kPointer).string();
    records_.emplace_back(pointer, register_temporary(pointer, false));
    journal::write_synced(pointer, journal::pointer_text(path));
  }
  const std::string tmp = path + ".tmp";
  records_.emplace_back(tmp, register_temporary(tmp, false));
  journal::write_synced(tmp, journal::journal_text(moves, staging_abs_));
  if (counted_rename(tmp, path) != 0)
    throw Error(path + ": cannot write the commit journal (" + errno_text() + ")");
  unregister_temporary(records_.back().second);
  records_.back() = {path, register_temporary(path, false)};  // the last record: removed first
  journal::sync_path(master);
}

void OutputTransaction::move_into_place() {
  for (auto& s : staged_) {
    if (counted_rename(s.staged, s.destination) != 0) {
      // past the commit point: the journal and the files not yet moved stay for the next run
      const std::string why = errno_text(), where = fs::path(s.staged).parent_path().string();
      for (const auto& t : staged_) unregister_temporary(t.slot);
      for (const auto& r : records_) unregister_temporary(r.second);
      for (const auto& d : staging_dirs_) unregister_temporary(d.second);
      for (const auto& d : created_dirs_) unregister_temporary(d.second);
      staged_.clear();
      records_.clear();
      staging_dirs_.clear();
      created_dirs_.clear();
      release_locks();
      committed_ = true;
      g_committing.store(false);
      throw Error(s.destination + ": cannot move the finished output into place (" + why +
                  "); the run's other outputs stay in " + where + " until a later run writing there completes them");
    }
    unregister_temporary(s.slot);
    s.slot = -1;
  }
}

void OutputTransaction::finish() noexcept {
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {  // the journal first: the commit is over
    ::unlink(it->first.c_str());
    unregister_temporary(it->second);
  }
  for (const auto& d : staging_dirs_) {
    ::rmdir(d.first.c_str());
    unregister_temporary(d.second);
  }
  for (const auto& d : created_dirs_) unregister_temporary(d.second);
  staged_.clear();
  records_.clear();
  staging_dirs_.clear();
  staging_for_.clear();
  staging_abs_.clear();
  created_dirs_.clear();
  release_locks();
}

void OutputTransaction::release_locks() noexcept {
  for (const auto& f : lock_files_) {  // removed while held: a waiting run then locks a new file
    ::unlink(f.first.c_str());
    unregister_temporary(f.second);
  }
  for (const int fd : lock_fds_) ::close(fd);
  lock_files_.clear();
  lock_fds_.clear();
}

void OutputTransaction::rollback() noexcept {
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {  // a journal first: nothing is committed
    ::unlink(it->first.c_str());
    unregister_temporary(it->second);
  }
  for (const auto& s : staged_) {
    if (s.slot >= 0) {
      ::unlink(s.staged.c_str());
      unregister_temporary(s.slot);
    }
  }
  for (const auto& d : staging_dirs_) {
    ::rmdir(d.first.c_str());
    unregister_temporary(d.second);
  }
  release_locks();  // (a lock file may be in a folder this run created)
  for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) {
    ::rmdir(it->first.c_str());
    unregister_temporary(it->second);
  }
  staged_.clear();
  records_.clear();
  staging_dirs_.clear();
  staging_for_.clear();
  staging_abs_.clear();
  created_dirs_.clear();
  if (const int sig = g_deferred_signal.load()) exit_on_signal(sig, ": interrupted; no outputs written\n");
}

}  // namespace vehs
