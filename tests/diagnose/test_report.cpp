#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "vehs/diagnose/report.hpp"

namespace fs = std::filesystem;

namespace {
// Renders the page in headless Chromium and returns the text of #figure-status after load.
std::string chromium_figure_status(const std::string& html) {
  const std::string profile = (fs::temp_directory_path() / "vehs_chromium_profile").string();
  fs::remove_all(profile);
  const std::string out = (fs::temp_directory_path() / "vehs_dom.html").string();
  const std::string cmd =
      "chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir=" + profile + " --virtual-time-budget=5000 --dump-dom 'file://" +
      fs::absolute(html).string() + "' > " + out + " 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) return "chromium failed";
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string dom = ss.str();
  const auto p = dom.find("figures-loaded:");
  if (p == std::string::npos) return "no status";
  return dom.substr(p, dom.find('<', p) - p);
}
}  // namespace

TEST_CASE("the HTML report embeds every figure and they load in headless Chromium", "[report]") {
  const std::string folder = (fs::temp_directory_path() / "vehs_report_test").string();
  fs::remove_all(folder);
  vehs::diagnose::Report report(folder, "Test report");
  auto& sec = report.section("Curves");
  sec.paragraphs.push_back("Two figures & a table <escaped>.");
  vehs::Table t({"x", "y"});
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
  vehs::diagnose::Report report(folder, "Bad");
  auto& sec = report.section("Broken");
  report.add_figure(sec, "broken", "a broken figure", "plot 'does-not-exist.csv' using 1:2");
  const auto html = report.write_html();
  std::ifstream in(html);
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("figure not rendered") != std::string::npos);
}
