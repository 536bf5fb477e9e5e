// All-or-nothing outputs and output-path safety (vehs/io/output_transaction.hpp; issue 17: inputs
// overwritten, devices and links replaced, partial report folders, temporary files left by signals).
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/output_transaction.hpp"

namespace fs = std::filesystem;

namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vehs_tx_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::set<std::string> listing(const fs::path& d) {
  std::set<std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(d)) s.insert(e.path().lexically_relative(d).string());
  return s;
}

}  // namespace

TEST_CASE("a committed transaction writes every output, an abandoned one none", "[io][outputs][asan]") {
  const fs::path d = fresh("commit");
  std::ofstream(d / "old.json") << "old";
  {
    vehs::OutputTransaction t;
    vehs::write_file_atomically((d / "old.json").string(), "new");
    vehs::write_file_atomically((d / "report" / "deep" / "a.csv").string(), "a");
    CHECK(slurp(d / "old.json") == "old");                // nothing in place before commit
    CHECK_FALSE(fs::exists(d / "report" / "deep" / "a.csv"));
    t.commit();
  }
  CHECK(slurp(d / "old.json") == "new");
  CHECK(slurp(d / "report" / "deep" / "a.csv") == "a");
  CHECK(listing(d) == std::set<std::string>{"old.json", "report", "report/deep", "report/deep/a.csv"});
  {
    vehs::OutputTransaction t;  // an error after some outputs: none of them appears
    vehs::write_file_atomically((d / "old.json").string(), "newer");
    vehs::write_file_atomically((d / "other" / "b.csv").string(), "b");
  }
  CHECK(slurp(d / "old.json") == "new");
  CHECK(listing(d) == std::set<std::string>{"old.json", "report", "report/deep", "report/deep/a.csv"});
  fs::remove_all(d);
}

TEST_CASE("no output may be an input, another output, a directory, device, pipe or link", "[io][outputs][asan]") {
  const fs::path d = fresh("checks");
  std::ofstream(d / "data.csv") << "t,x\n";
  fs::create_hard_link(d / "data.csv", d / "hard.csv");
  fs::create_symlink(d / "data.csv", d / "link.csv");
  fs::create_symlink("/dev/null", d / "null.json");
  fs::create_directories(d / "dir");
  REQUIRE(::mkfifo((d / "fifo").c_str(), 0600) == 0);
  {
    vehs::OutputTransaction t;
    t.protect((d / "data.csv").string(), "input 'data'");
    const std::string sub = (d / "dir" / ".." / "data.csv").string();
    CHECK_THROWS_WITH(vehs::write_file_atomically(sub, "x"), Catch::Contains("is the input 'data'"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "hard.csv").string(), "x"), Catch::Contains("is the input"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "link.csv").string(), "x"), Catch::Contains("symbolic link"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "null.json").string(), "x"), Catch::Contains("symbolic link"));
    CHECK_THROWS_WITH(vehs::write_file_atomically("/dev/null", "x"), Catch::Contains("device, pipe or socket"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "fifo").string(), "x"), Catch::Contains("device, pipe"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "dir").string(), "x"), Catch::Contains("is a directory"));
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / std::string(300, 'o')).string(), "x"), Catch::Contains("longer than the 255"));
    vehs::write_file_atomically((d / "out.json").string(), "1");
    CHECK_THROWS_WITH(vehs::write_file_atomically((d / "." / "out.json").string(), "2"), Catch::Contains("written twice by this run"));
  }
  CHECK(slurp(d / "data.csv") == "t,x\n");
  CHECK_FALSE(fs::exists(d / "out.json"));
  CHECK(fs::is_symlink(d / "null.json"));
  CHECK(listing(d) == std::set<std::string>{"data.csv", "hard.csv", "link.csv", "null.json", "dir", "fifo"});
  fs::remove_all(d);
}

TEST_CASE("an input read after its output was staged still stops the commit", "[io][outputs][asan]") {
  const fs::path d = fresh("late");
  std::ofstream(d / "model.json") << "{}";
  {
    vehs::OutputTransaction t;
    vehs::write_file_atomically((d / "model.json").string(), "overwritten");
    t.protect((d / "model.json").string(), "model file");
    CHECK_THROWS_WITH(t.commit(), Catch::Contains("is the model file"));
  }
  CHECK(slurp(d / "model.json") == "{}");
  CHECK(listing(d) == std::set<std::string>{"model.json"});
  fs::remove_all(d);
}

TEST_CASE("SIGTERM and SIGINT during a run remove staged and temporary files - status 143 and 130",
          "[io][outputs]") {
  for (const int sig : {SIGTERM, SIGINT}) {
    const fs::path d = fresh("signal" + std::to_string(sig));
    std::ofstream(d / "keep.txt") << "k";
    int ready[2];
    REQUIRE(::pipe(ready) == 0);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {  // the child: stages outputs, then waits inside a write to be killed
      vehs::install_signal_cleanup("child");
      vehs::OutputTransaction t;
      vehs::write_file_atomically((d / "new" / "a.json").string(), std::string(1 << 20, 'a'));
      vehs::write_file_atomically((d / "b.json").string(), [&](std::ostream& os) {
        os << "partial" << std::flush;
        (void)!::write(ready[1], "r", 1);
        for (;;) ::pause();
      });
      ::_exit(0);
    }
    char c = 0;
    REQUIRE(::read(ready[0], &c, 1) == 1);
    CHECK(listing(d).size() > 1);  // staged files exist while the child works
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ::close(ready[0]);
    ::close(ready[1]);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 128 + sig);
    CHECK(listing(d) == std::set<std::string>{"keep.txt"});
    fs::remove_all(d);
  }
}

TEST_CASE("without a transaction a write still refuses links and devices and leaves no temporary",
          "[io][outputs][asan]") {
  const fs::path d = fresh("plain");
  fs::create_symlink("/dev/null", d / "null.json");
  CHECK_THROWS_WITH(vehs::write_file_atomically((d / "null.json").string(), "x"), Catch::Contains("symbolic link"));
  vehs::write_file_atomically((d / std::string(250, 'n')).string(), "long names fit");  // 250 < NAME_MAX
  CHECK(slurp(d / std::string(250, 'n')) == "long names fit");
  CHECK(listing(d) == std::set<std::string>{"null.json", std::string(250, 'n')});
  fs::remove_all(d);
}

namespace {

// A child that replaces a.json and sub/b.json in one transaction and is killed at rename k.
int commit_killed_at(const fs::path& d, int k) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setenv("VEHS_TEST_KILL_AT_RENAME", std::to_string(k).c_str(), 1);
    vehs::OutputTransaction t;
    vehs::write_file_atomically((d / "a.json").string(), "new a");
    vehs::write_file_atomically((d / "sub" / "b.json").string(), "new b");
    t.commit();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

bool no_staging_left(const fs::path& d) {
  for (const auto& e : fs::recursive_directory_iterator(d))
    if (e.path().filename().string().rfind(".vehs-", 0) == 0) return false;
  return true;
}

}  // namespace

TEST_CASE("a commit killed at any rename is completed or undone by the next run in its folders",
          "[io][outputs][journal]") {
  for (int k = 1; k <= 4; ++k) {
    CAPTURE(k);
    const fs::path d = fresh("journal" + std::to_string(k));
    fs::create_directories(d / "sub");
    std::ofstream(d / "a.json") << "old a";
    std::ofstream(d / "sub" / "b.json") << "old b";
    const int status = commit_killed_at(d, k);
    if (k <= 3) {  // the journal's rename, then the two outputs'
      REQUIRE(WIFSIGNALED(status));
      CHECK(WTERMSIG(status) == SIGKILL);
      CHECK_FALSE(no_staging_left(d));
    } else {
      CHECK(WIFEXITED(status));
    }
    vehs::recover_stale_outputs((d / "sub").string());  // either folder repairs the whole commit
    const std::string a = slurp(d / "a.json"), b = slurp(d / "sub" / "b.json");
    CHECK(((a == "old a" && b == "old b") || (a == "new a" && b == "new b")));
    CHECK((k == 1 ? a == "old a" : a == "new a"));  // past the journal's rename: completed
    vehs::recover_stale_outputs(d.string());
    CHECK(no_staging_left(d));
    fs::remove_all(d);
  }
}

TEST_CASE("a stale staging folder without a journal is removed with the folders its run created",
          "[io][outputs][journal]") {
  const fs::path d = fresh("stale_created");
  const pid_t pid = ::fork();
  if (pid == 0) {  // stages into new folders, then dies before committing
    vehs::OutputTransaction t;
    vehs::write_file_atomically((d / "figs" / "deep" / "f.csv").string(), "f");
    ::raise(SIGKILL);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(fs::exists(d / "figs" / "deep"));
  {
    vehs::OutputTransaction t;  // a later run checking an output there repairs the folder first
    t.check_output((d / "figs" / "deep" / "g.csv").string());
  }
  CHECK(listing(d).empty());
  fs::remove_all(d);
}

TEST_CASE("an output name starting with .vehs- is refused", "[io][outputs]") {
  CHECK_THROWS_WITH(vehs::check_output_path("out/.vehs-commit"), Catch::Contains("reserved"));
}

TEST_CASE("a folder reached through a link holds this run's staging folder - not a stale one",
          "[io][outputs][journal]") {
  const fs::path d = fresh("linked");
  fs::create_directories(d / "out");
  fs::create_directory_symlink(d / "out", d / "link");
  {
    vehs::OutputTransaction t;
    vehs::write_file_atomically((d / "out" / "a.json").string(), "a");
    vehs::write_file_atomically((d / "link" / "b.json").string(), "b");
    t.commit();
  }
  CHECK(slurp(d / "out" / "a.json") == "a");
  CHECK(slurp(d / "out" / "b.json") == "b");
  CHECK(no_staging_left(d));
  fs::remove_all(d);
}
