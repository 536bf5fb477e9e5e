#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "chromium.hpp"
#include "tools/html_report.hpp"

namespace fs = std::filesystem;

using diag_test::chromium_figure_status;

TEST_CASE("the HTML report embeds every figure and they load in headless Chromium", "[report]") {
  const std::string folder = (fs::temp_directory_path() / "vehs_report_test").string();
  fs::remove_all(folder);
  vehs::tools::Report report(folder, "Test report");
  auto& sec = report.section("Curves");
  sec.paragraphs.push_back("Two figures & a table <escaped>.");
  vehs::tools::Table t({"x", "y"});
  for (int i = 0; i < 50; ++i) t.add_row({i * 0.1, std::sin(i * 0.1)});
  report.add_figure(sec, "sine", "a sine", t, "plot 'sine.csv' using 1:2 skip 1 with lines title 'sin'");
  report.add_figure(sec, "sine2", "the same, as points", t, "plot 'sine.csv' using 1:2 skip 1 with points title 'sin'");
  sec.tables.push_back({"numbers", {"a", "b"}, {{"1", "2"}, {"3", "4"}}, {1}});
  const auto html = report.write_html();
  REQUIRE(fs::exists(html));
  for (const char* f : {"sine.svg", "sine.gp", "sine.csv", "sine2.svg"}) CHECK(fs::exists(fs::path(folder) / f));
  std::ifstream in(html);
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("&amp; a table &lt;escaped&gt;") != std::string::npos);
  CHECK(chromium_figure_status(html) == "figures-loaded: 2/2");
}

TEST_CASE("a figure that cannot render is reported in the page, not silently dropped", "[report]") {
  const std::string folder = (fs::temp_directory_path() / "vehs_report_bad").string();
  fs::remove_all(folder);
  vehs::tools::Report report(folder, "Bad");
  auto& sec = report.section("Broken");
  report.add_figure(sec, "broken", "a broken figure", "plot 'does-not-exist.csv' using 1:2");
  const auto html = report.write_html();
  std::ifstream in(html);
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("figure not rendered") != std::string::npos);
}

TEST_CASE("a report section's reference stays valid while further sections are added", "[tools][report]") {
  vehs::tools::Report report((fs::temp_directory_path() / "vehs_report_sections").string(), "sections");
  vehs::tools::ReportSection& first = report.section("first");
  for (int i = 0; i < 100; ++i) report.section("section " + std::to_string(i));
  first.paragraphs.push_back("still here");  // a vector of sections moved it: a dangling reference
  CHECK(&report.section("first") == &first);
  CHECK(report.section("first").paragraphs.size() == 1);
}
