#pragma once
// Renders an HTML page in headless Chromium (Debian's chromium package) and returns the text of
// its #figure-status element after load ("figures-loaded: N/M"), or why it could not.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>

namespace diag_test {

inline std::string chromium_figure_status(const std::string& html) {
  namespace fs = std::filesystem;
  const std::string tag = std::to_string(std::hash<std::string>{}(html));
  const std::string profile = (fs::temp_directory_path() / ("vehs_chromium_profile_" + tag)).string();
  fs::remove_all(profile);
  const std::string out = (fs::temp_directory_path() / ("vehs_dom_" + tag + ".html")).string();
  const std::string cmd =
      "chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir=" + profile + " --virtual-time-budget=5000 --dump-dom 'file://" +
      fs::absolute(html).string() + "' > " + out + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  fs::remove_all(profile);
  if (rc != 0) return "chromium failed";
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string dom = ss.str();
  const auto p = dom.find("figures-loaded:");
  if (p == std::string::npos) return "no status";
  return dom.substr(p, dom.find('<', p) - p);
}

}  // namespace diag_test
