#include "tools/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "vehs/io/output_transaction.hpp"

extern char** environ;

namespace vehs::tools {

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return std::filesystem::absolute(candidate).string();
  }
  return "";
}

namespace {

/// Signals the tools' handler acts on: blocked from before the child starts until its pid is
/// registered, so that an interrupt can never miss a running child.
sigset_t cleanup_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
  return set;
}

struct SpawnSetup {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  SpawnSetup(const std::string& cwd, const std::string& stderr_file) {
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderr_file.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_init(&attr);
    // the child starts with the default disposition and an empty mask for every signal we handle
    sigset_t none, handled = cleanup_signals();
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &handled);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
  }
};

}  // namespace

int run_program(const std::vector<std::string>& argv, const std::string& cwd, const std::string& stderr_file) {
  if (argv.empty()) return -1;
  const std::string program = find_on_path(argv[0]);
  if (program.empty()) return -1;
  std::vector<char*> args{const_cast<char*>(program.c_str())};
  for (std::size_t i = 1; i < argv.size(); ++i) args.push_back(const_cast<char*>(argv[i].c_str()));
  args.push_back(nullptr);
  SpawnSetup setup(cwd, stderr_file);
  const sigset_t handled = cleanup_signals();
  sigset_t previous;
  pthread_sigmask(SIG_BLOCK, &handled, &previous);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, args[0], &setup.actions, &setup.attr, args.data(), environ);
  if (spawned == 0) register_child(pid);
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (spawned != 0) return -1;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  unregister_child();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace vehs::tools
