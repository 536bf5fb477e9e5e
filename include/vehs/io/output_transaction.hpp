#pragma once
// All-or-nothing outputs. While an OutputTransaction is open, every write_file_atomically() of the
// process (model files, statistics, reports, figures, history) goes into a staging folder next to
// its destination (<dir>/.vehs-staging.<pid>/<name>); commit() moves every staged file into place
// by rename(2) at the end of the run, and a transaction destroyed without commit() (an error, an
// exception) removes the staged files, the staging folders and the folders it created. A signal
// handler (install_signal_cleanup) removes the same on SIGINT/SIGTERM/SIGHUP and exits 128+signal.
//
// Every output path is checked before anything is written (check_output_path): it must not be a
// directory, a device, a pipe or a symbolic link (rename would replace the link, and a device such
// as /dev/null would be replaced for everyone), its name must fit NAME_MAX, and, inside a
// transaction, it must not be a protected input (same st_dev/st_ino) or another output of the same
// run (same canonical path or same file).
#include <string>
#include <sys/types.h>
#include <utility>
#include <vector>

namespace vehs {

/// Throws vehs::Error naming `path` when it cannot be an output: an existing directory, device,
/// pipe, socket or symbolic link, an empty name or a name longer than NAME_MAX bytes.
void check_output_path(const std::string& path);

class OutputTransaction {
 public:
  /// Opens the process's transaction (one at a time; throws when one is open).
  OutputTransaction();
  /// Without commit(): removes everything staged and every folder created.
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// The open transaction, or nullptr.
  static OutputTransaction* active();

  /// Marks an existing file as an input of the run: no output may be the same file. Paths that do
  /// not name an existing regular file are ignored. `what` names its role in error messages.
  void protect(const std::string& path, const std::string& what);
  /// Checks `path` as an output of this run (check_output_path, not an input, not another output)
  /// without staging it: tools call it for their main outputs before the long work.
  void check_output(const std::string& path) const;

  /// Stages `destination`: checks it, creates its folder and the staging folder, and returns the
  /// path to write the content to. Used by write_file_atomically.
  std::string stage(const std::string& destination);
  /// The staging folder of destination folder `dir` (created), for programs that write files
  /// themselves (gnuplot); adopt() then stages a file they wrote there.
  std::string staging_directory(const std::string& dir);
  void adopt(const std::string& destination);

  /// Where the content written for `destination` is now: its staged file when this transaction
  /// staged it, else `destination` itself (for code that reads back an output of the same run).
  std::string current_path(const std::string& destination) const;

  /// Moves every staged file into place; the run's outputs then exist together.
  void commit();
  std::size_t staged_count() const { return staged_.size(); }

 private:
  struct Identity {
    dev_t dev;
    ino_t ino;
  };
  struct Input {
    Identity id;
    std::string path, what;
  };
  struct Staged {
    std::string staged, destination, canonical;
    int slot;
  };
  void make_directories(const std::string& dir);
  void rollback() noexcept;

  std::vector<Input> inputs_;
  std::vector<Staged> staged_;
  std::vector<std::pair<std::string, int>> created_dirs_;    ///< folders this run created (path, slot)
  std::vector<std::pair<std::string, int>> staging_dirs_;    ///< destination folder's staging folder
  std::vector<std::string> staging_for_;                     ///< the destination folder of each
  bool committed_ = false;
};

/// OutputTransaction::active()->current_path(destination), or `destination` outside a transaction.
std::string current_output_path(const std::string& destination);

/// Temporary files and folders removed by the signal handler (async-signal-safe storage).
/// register_temporary returns a slot for unregister_temporary.
int register_temporary(const std::string& path, bool directory);
void unregister_temporary(int slot) noexcept;
/// Installs handlers for SIGINT, SIGTERM and SIGHUP that stop the registered child process (if
/// any), remove every registered temporary file and folder, print one line and exit with status
/// 128 + signal (130 for SIGINT, 143 for SIGTERM).
void install_signal_cleanup(const char* program);

/// The external program the process is waiting for (one at a time: gnuplot), which the signal
/// handler kills and reaps before it removes the temporaries the program may still be writing.
void register_child(pid_t pid) noexcept;
void unregister_child() noexcept;

}  // namespace vehs
