#pragma once
// The journal that makes a commit of several outputs recoverable when the process is killed
// (SIGKILL, a power cut) between its renames.
//
// A transaction stages its outputs in one staging folder per destination folder
// (<dir>/.vehs-staging.<pid>/). commit() first writes, in every staging folder but the first, a
// pointer file naming the master journal (kPointer), then the master journal itself in the first
// folder (kJournal: every staged absolute path and its destination, and every staging folder),
// written to a temporary, fsynced and renamed: that rename is the commit point. Then the outputs
// are renamed into place, the journal is removed, then the pointers and the staging folders.
//
// A later run, before it writes into a folder or reads a previous output from it, repairs the
// staging folders there whose process is gone (recover_stale_staging): with a journal (its own or
// the one its pointer names) the commit is completed (roll forward: every staged file still there
// is renamed to its destination, then all the transaction's staging folders are removed);
// without one the run never reached its commit point and its staged files are deleted (roll
// back), with the folders it created for them (kCreated) when they are empty.
#include <string>
#include <vector>

namespace vehs::journal {

inline constexpr const char* kStagingPrefix = ".vehs-staging.";
inline constexpr const char* kJournal = ".vehs-commit";      ///< the master journal
inline constexpr const char* kPointer = ".vehs-commit-at";   ///< the master journal's path
inline constexpr const char* kCreated = ".vehs-created";     ///< folders created for this staging folder

struct Move {
  std::string staged, destination;  ///< absolute paths
};

/// The master journal's and a pointer's content.
std::string journal_text(const std::vector<Move>& moves, const std::vector<std::string>& folders);
std::string pointer_text(const std::string& journal_path);
std::string created_text(const std::vector<std::string>& folders);

/// Writes `content` to `path` and fsyncs it; throws vehs::Error naming `what`'s path.
void write_synced(const std::string& path, const std::string& content);
/// fsync of an existing file or folder; throws vehs::Error naming it.
void sync_path(const std::string& path);

/// Repairs every stale staging folder of `dir` (its process is gone, or it has this process's id
/// but is not in `own`, the absolute staging folders of this process's open transaction) and
/// removes stale temporaries of write_file_atomically (.vehs-tmp.<pid>.<n>). Prints one line on
/// stderr, prefixed by `program`, per folder repaired. Throws vehs::Error when a staged output
/// cannot be moved into place.
void recover_stale_staging(const std::string& dir, const std::vector<std::string>& own, const char* program);

}  // namespace vehs::journal
