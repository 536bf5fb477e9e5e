// fpk-stationary on a large grid: the estimate before the factorisation, its phases announced,
// and SIGINT/SIGTERM inside UMFPACK's symbolic or numeric phase stop the tool at once (status
// 128 + signal) leaving nothing in the output folder (issue 17).
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace fs = std::filesystem;

extern char** environ;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Starts `exe arg` with stderr into `log`; returns the pid.
pid_t spawn(const std::string& exe, const std::string& arg, const fs::path& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  std::string e = exe, a = arg;
  char* argv[] = {e.data(), a.data(), nullptr};
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, e.c_str(), &fa, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  REQUIRE(rc == 0);
  return pid;
}

/// Waits up to `limit` for `pid`; its wait status, or -1 after killing it (a hang).
int wait_for(pid_t pid, std::chrono::duration<double> limit) {
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (std::chrono::steady_clock::now() - start < limit) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -1;
}

}  // namespace

TEST_CASE("fpk-stationary: a signal inside the factorisation stops it and leaves no files", "[tools][signal]") {
  const fs::path dir = fs::temp_directory_path() / ("vehs_fpk_interrupt_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  fs::copy_file(fs::path(VEHS_SOURCE_DIR) / "data/paper/truth.json", dir / "model.json");
  // 1000² cells: ~15 s of factorisation on an idle core, far longer than the signal takes
  std::ofstream(dir / "cfg.json") << R"({"model": ")" << (dir / "model.json").string()
                                  << R"(", "grid": {"x": 1000, "y": 1000}, "figures": ")" << (dir / "out/figs").string()
                                  << R"(", "output": ")" << (dir / "out/fpk.json").string() << "\"}";
  const std::string exe = (fs::path(VEHS_BINARY_DIR) / "fpk-stationary").string();
  for (const auto& [sig, phase] : {std::pair{SIGTERM, std::string("(symbolic)...")}, std::pair{SIGINT, std::string("(numeric)...")}}) {
    CAPTURE(sig, phase);
    const fs::path log = dir / ("stderr" + std::to_string(sig) + ".txt");
    const pid_t pid = spawn(exe, (dir / "cfg.json").string(), log);
    // the estimate, then each phase announced before it starts
    const auto start = std::chrono::steady_clock::now();
    while (read_text(log).find(phase) == std::string::npos &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const std::string before = read_text(log);
    REQUIRE(before.find("factorising 1000x1000 cells " + phase) != std::string::npos);
    CHECK(before.find("1000x1000 cells: about ") != std::string::npos);
    CHECK(before.find(" GB of memory per solve") != std::string::npos);
    CHECK(before.find("factorised in") == std::string::npos);  // still inside the phase
    const auto signalled = std::chrono::steady_clock::now();
    REQUIRE(::kill(pid, sig) == 0);
    const int status = wait_for(pid, std::chrono::seconds(10));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
    REQUIRE(status != -1);  // not a hang
    CHECK(seconds < 3.0);   // promptly (the handler exits at once; 3 s allows a loaded machine)
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 128 + sig);
    CHECK(read_text(log).find("interrupted") != std::string::npos);
    for (const auto& f : fs::recursive_directory_iterator(dir / "out")) FAIL_CHECK("left behind: " << f.path());
  }
  fs::remove_all(dir);
}
