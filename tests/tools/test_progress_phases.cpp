// Progress that tracks the real work (issue 35, "silent minutes"): a driven fit whose likelihood
// refinement takes most of the call reports through to its end, from the library's callback and
// as identify-vehs's stderr lines when stderr is not a terminal.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "fit/driven_record.hpp"
#include "progress_checks.hpp"
#include "tool_runs.hpp"
#include "vehs/fit/fit.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"

namespace fs = std::filesystem;
using vehs_tool_test::RecordedEvent;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A driven linear oscillator sampled coarsely (ω·dt 0.5: the sampling cannot vouch for the moment
/// fit, the likelihood refines it from every start and selects), sensor noise 0.01, an AR(1) input
/// held over each interval.
vehs::Dataset driven(std::size_t n, std::uint64_t seed) { return fit_test::driven(0.5, n, seed); }

}  // namespace

TEST_CASE("vehs::fit reports every phase of a driven fit through to its end", "[fit][progress]") {
  const vehs::Dataset d = driven(12000, 11);
  std::vector<RecordedEvent> events;
  std::mutex m;
  vehs::FitOptions o;
  const Clock::time_point t0 = Clock::now();
  o.progress = [&](const vehs::ProgressEvent& e) {
    std::lock_guard<std::mutex> lock(m);
    events.push_back({std::string(e.task), e.done, e.total, e.finished, since(t0)});
  };
  const vehs::FitSummary s = vehs::fit(d, o);
  const double wall = since(t0);
  REQUIRE(s.refinement.result);  // the likelihood ran: the long phase of the call
  std::string tasks;
  for (const RecordedEvent& e : events)
    if (tasks.find("[" + e.task + "]") == std::string::npos) tasks += "[" + e.task + "]";
  INFO("wall " << wall << " s; tasks " << tasks);
  CHECK(tasks.find("[likelihood fit]") != std::string::npos);
  // the heartbeat is every 0.5 s; 2 s leaves room for a loaded machine
  CHECK(vehs_tool_test::progress_problems(events, wall, 2.0) == "");
}

TEST_CASE("identify-vehs prints progress lines through to the end when stderr is not a terminal",
          "[identify][app][progress]") {
  const fs::path dir = vehs_tool_test::work_dir("test_progress_cli");
  // long enough that the likelihood phase outlasts the 0.5 s below which a finished phase prints
  // no line, on a machine several times faster than a loaded laptop core
  vehs::write_measurements((dir / "driven.csv").string(), driven(96000, 11), vehs::WriteColumns{false, true, 17});
  const fs::path cfg = dir / "identify.json";
  std::ofstream(cfg) << "{\"data\": \"" << (dir / "driven.csv").string() << "\", \"output\": \""
                     << (dir / "model.json").string() << "\"}";
  const std::string cmd = "'" + (fs::path(VEHS_BINARY_DIR) / "identify-vehs").string() + "' '" + cfg.string() +
                          "' 2>&1 >/dev/null";
  const Clock::time_point t0 = Clock::now();
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  // one per progress line ("[task] ..."; the likelihood's own log lines are not progress): its text
  // as the task, its arrival time
  std::vector<RecordedEvent> lines;
  std::string all;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) {
    all += buf;
    if (buf[0] == '[') lines.push_back({buf, 0, 0, false, since(t0)});
  }
  const int status = ::pclose(p);
  const double wall = since(t0);
  std::string text;
  for (const RecordedEvent& l : lines) text += std::to_string(l.at).substr(0, 5) + " " + l.task;
  INFO("wall " << wall << " s; progress lines:\n" << text << "stderr:\n" << all);
  REQUIRE(status == 0);
  CHECK(text.find("[likelihood fit]") != std::string::npos);
  // a line every 2 s at most while a phase runs (0.5 s heartbeat): 3 s leaves room for load
  CHECK(vehs_tool_test::progress_problems(lines, wall, 3.0) == "");
}
