#pragma once
// Renders an HTML page in headless Chromium (Debian's chromium package): the DOM after load, and
// from it the count of figures that decoded ("figures-loaded: N/M", from the page's
// data-figures-loaded attribute, which the page does not show), or why it could not.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>

namespace diag_test {

/// The DOM of the page after load, or "" when Chromium failed.
inline std::string chromium_dom(const std::string& html) {
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
  if (rc != 0) return "";
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string chromium_figure_status(const std::string& html) {
  const std::string dom = chromium_dom(html);
  if (dom.empty()) return "chromium failed";
  const std::string key = "data-figures-loaded=\"";
  const auto p = dom.find(key);
  if (p == std::string::npos) return "no status";
  const auto b = p + key.size();
  return "figures-loaded: " + dom.substr(b, dom.find('"', b) - b);
}

}  // namespace diag_test
