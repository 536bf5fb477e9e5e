// identify-vehs --refit FILE (tools/refit_source.hpp): a diagnosis file leads to the refit config
// its refit_file names (beside it when the report folder moved), a refit config is run as it is,
// and every file that describes no refit is one line naming it with exit status 1. The run of a
// real diagnosis is in test_diagnose_tool.cpp (diagnose-vehs end to end).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "tool_runs.hpp"
#include "tools/refit_source.hpp"
#include "vehs/core/error.hpp"

namespace fs = std::filesystem;

namespace {

fs::path write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

/// identify-vehs --refit `file`: exit status; `err` gets its stderr.
int refit(const fs::path& file, std::string& err) {
  return vehs_tool_test::run_identify({"--refit", file.string(), "-q"}, &err);
}

bool one_line_naming(const std::string& err, const fs::path& file) {
  return err.find(file.string()) != std::string::npos && err.find('\n') == err.size() - 1;
}

}  // namespace

TEST_CASE("identify-vehs --refit finds the refit config of a diagnosis", "[tools][refit]") {
  const fs::path dir = vehs_tool_test::work_dir("refit_source");
  fs::remove_all(dir);
  const fs::path config = write(dir / "report" / "refit.json", R"({"data": ["rig.csv"], "effects": ["coulomb_friction"]})");
  const fs::path diagnosis =
      write(dir / "diagnosis.json", R"({"verdict": "inadequate", "refit_file": ")" + config.string() + R"("})");
  CHECK(vehs::tools::refit_config_for(diagnosis.string()) == config.string());
  CHECK(vehs::tools::refit_config_for(config.string()) == config.string());  // a refit config as it is
  // the report folder moved: its summary.json names the old place, the config lies beside it
  const fs::path moved = dir / "moved";
  fs::rename(dir / "report", moved);
  const fs::path summary =
      write(moved / "summary.json", R"({"verdict": "inadequate", "refit_file": ")" + config.string() + R"("})");
  CHECK(vehs::tools::refit_config_for(summary.string()) == (moved / "refit.json").string());
}

TEST_CASE("identify-vehs --refit refuses a file that describes no refit in one line", "[tools][refit]") {
  const fs::path dir = vehs_tool_test::work_dir("refit_bad");
  fs::remove_all(dir);
  std::string err;
  const fs::path adequate = write(dir / "adequate.json", R"({"verdict": "adequate", "refit_config": null, "refit_file": null})");
  CHECK(refit(adequate, err) == 1);
  CHECK(one_line_naming(err, adequate));
  CHECK(err.find("recommends no refit") != std::string::npos);
  const fs::path gone = write(dir / "gone.json", R"({"verdict": "inadequate", "refit_file": "/nonexistent/refit.json"})");
  CHECK(refit(gone, err) == 1);
  CHECK(one_line_naming(err, gone));
  CHECK(err.find("/nonexistent/refit.json does not exist") != std::string::npos);
  const fs::path other = write(dir / "other.json", R"({"drift": {"x": -1}})");
  CHECK(refit(other, err) == 1);
  CHECK(one_line_naming(err, other));
  CHECK(err.find("neither a diagnosis file") != std::string::npos);
  const fs::path text = write(dir / "text.json", "not json");
  CHECK(refit(text, err) == 1);
  CHECK(one_line_naming(err, text));
  CHECK(refit(dir / "missing.json", err) == 1);
  CHECK(one_line_naming(err, dir / "missing.json"));
  // CONFIG and --refit together is a usage error (exit 2)
  CHECK(vehs_tool_test::run_identify({other.string(), "--refit", adequate.string()}, &err) == 2);
}
