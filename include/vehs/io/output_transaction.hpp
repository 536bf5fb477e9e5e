#pragma once
// All-or-nothing outputs. While an OutputTransaction is open, every write_file_atomically() of the
// process (model files, statistics, reports, figures, history) goes into a staging folder next to
// its destination (<dir>/.vehs-staging.<pid>/<name>); commit() moves every staged file into place
// by rename(2) at the end of the run, and a transaction destroyed without commit() (an error, an
// exception) removes the staged files, the staging folders and the folders it created. A signal
// handler (install_signal_cleanup) removes the same on SIGINT/SIGTERM/SIGHUP and exits 128+signal.
//
// A kill that no handler sees (SIGKILL, a power cut) during commit() is repaired by the next run
// writing to the same folder: commit() writes a journal before its first rename (src/io/
// commit_journal.hpp), and before a transaction writes into a folder, or checks an output there,
// it completes the commit of a dead process whose journal is there, or deletes the staged files
// of one that died before its journal (recover_stale_outputs). The outputs of a run are thus
// either all old or all new once a later run has looked at their folders.
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
/// pipe, socket or symbolic link, an empty name, a name longer than NAME_MAX bytes or one starting
/// with ".vehs-" (the names of staging folders, journals and temporaries).
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

  /// Serialises a read-modify-write output (the model history): takes an exclusive flock(2) on
  /// `destination`.lock (created beside it) and holds it until commit() has moved the outputs into
  /// place, or until the transaction rolls back; the lock file is removed then. Call it before
  /// reading the file's previous content. Blocks while another process holds it.
  void lock_output(const std::string& destination);

  /// Moves every staged file into place; the run's outputs then exist together. Before the first
  /// rename a journal is written (the commit point): a kill after it is completed by the next run.
  /// For tests only: the environment variable VEHS_TEST_KILL_AT_RENAME=k raises SIGKILL just before
  /// the k-th rename (1: the journal's, 2...: the outputs').
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
  friend void recover_stale_outputs(const std::string& dir);
  void make_directories(const std::string& dir);
  void recover(const std::string& dir) const;
  void write_journal();
  void move_into_place();
  void finish() noexcept;
  void release_locks() noexcept;
  void rollback() noexcept;

  std::vector<Input> inputs_;
  std::vector<Staged> staged_;
  std::vector<std::pair<std::string, int>> created_dirs_;    ///< folders this run created (path, slot)
  std::vector<std::pair<std::string, int>> staging_dirs_;    ///< destination folder's staging folder
  std::vector<std::string> staging_for_;                     ///< the destination folder of each
  std::vector<std::string> staging_abs_;                     ///< each staging folder, absolute
  std::vector<std::pair<std::string, int>> records_;         ///< journal, pointers, created-folder lists
  std::vector<std::pair<std::string, int>> lock_files_;      ///< lock_output's files (path, slot)
  std::vector<int> lock_fds_;
  mutable std::vector<std::string> recovered_;               ///< folders already repaired
  bool committed_ = false;
};

/// Repairs the staging folders that killed runs left in `dir` (see OutputTransaction::commit):
/// completes a commit whose journal was written, else deletes its staged files. Prints one line
/// on stderr per folder repaired. Called by a transaction for every folder it writes to; call it
/// before reading a previous output of the tools (the history does).
void recover_stale_outputs(const std::string& dir);

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
