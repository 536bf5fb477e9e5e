#include "tools/html_report.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tools/figures.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/output_transaction.hpp"
#include "vehs/core/error.hpp"

namespace vehs::tools {

namespace fs = std::filesystem;

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

std::string base64(const std::string& in) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) | static_cast<unsigned char>(in[i + 2]);
    out += tbl[(v >> 18) & 63], out += tbl[(v >> 12) & 63], out += tbl[(v >> 6) & 63], out += tbl[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    out += tbl[(v >> 18) & 63], out += tbl[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    out += tbl[(v >> 18) & 63], out += tbl[(v >> 12) & 63], out += tbl[(v >> 6) & 63], out += '=';
  }
  return out;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

const char* kStyle = R"CSS(
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em; color: #222; }
h1 { font-size: 1.6em; border-bottom: 2px solid #446; padding-bottom: .3em; }
h2 { font-size: 1.25em; margin-top: 2em; color: #335; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: .92em; color: #444; margin-top: .4em; }
figcaption .files { font-size: .85em; color: #777; }
table { border-collapse: collapse; margin: 1em 0; font-size: .92em; }
th, td { border: 1px solid #ccc; padding: .25em .6em; text-align: right; }
th { background: #eef; }
td:first-child, th:first-child { text-align: left; }
tr.highlight td { background: #fdd; }
caption { caption-side: top; text-align: left; font-weight: 600; padding-bottom: .3em; }
.missing { color: #a00; font-style: italic; }
td { max-width: 24em; overflow-wrap: anywhere; }
section.card { border: 2px solid #446; border-radius: 6px; padding: .2em 1.2em 1em; background: #f7f8fc; }
section.card h2 { margin-top: .6em; }
pre { background: #272822; color: #f8f8f2; padding: .6em 1em; border-radius: 4px; overflow-x: auto; }
.verdict-adequate { color: #1a7a2e; font-weight: 700; }
.verdict-inadequate { color: #b2182b; font-weight: 700; }
)CSS";

// After load: count figures that decoded into an attribute of the page (not shown) for
// automated checks.
const char* kCheckScript = R"JS(
window.addEventListener('load', function () {
  var imgs = document.querySelectorAll('figure img');
  var ok = 0;
  imgs.forEach(function (im) { if (im.complete && im.naturalWidth > 0) ok++; });
  document.documentElement.setAttribute('data-figures-loaded', ok + '/' + imgs.length);
});
)JS";

}  // namespace

ReportSection& Report::section(const std::string& title) {
  for (auto& s : sections_)
    if (s.title == title) return s;
  ReportSection s;
  s.title = title;
  sections_.push_back(std::move(s));
  return sections_.back();
}

void Report::add_figure(ReportSection& sec, const std::string& name, const std::string& caption,
                        const Table& data, const std::string& gnuplot_body) {
  data.write_csv((fs::path(folder_) / (name + ".csv")).string());
  add_figure(sec, name, caption, gnuplot_body);
}

void Report::add_figure(ReportSection& sec, const std::string& name, const std::string& caption,
                        const std::string& gnuplot_body) {
  const bool ok = !render_figure(folder_, name, gnuplot_body, "svg", 820, 540).empty();
  sec.figures.push_back({name, caption, ok});
}

std::size_t Report::figure_count() const {
  std::size_t n = 0;
  for (const auto& s : sections_) n += s.figures.size();
  return n;
}

std::string Report::write_html() const {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
    << html_escape(title_) << "</title>\n<style>" << kStyle << "</style></head>\n<body>\n<h1>"
    << html_escape(title_) << "</h1>\n";
  for (const auto& s : sections_) {
    h << "<section" << (s.id.empty() ? "" : " id=\"" + html_escape(s.id) + "\"") << (s.card ? " class=\"card\"" : "")
      << ">\n<h2>" << html_escape(s.title) << "</h2>\n";
    for (const auto& p : s.paragraphs) h << "<p>" << html_escape(p) << "</p>\n";
    for (const auto& c : s.code) h << "<pre><code>" << html_escape(c) << "</code></pre>\n";
    if (!s.links.empty()) {
      h << "<ul>";
      for (const auto& l : s.links)
        h << "<li><a href=\"" << html_escape(l.href) << "\">" << html_escape(l.text) << "</a></li>";
      h << "</ul>\n";
    }
    for (const auto& t : s.tables) {
      h << "<table>";
      if (!t.caption.empty()) h << "<caption>" << html_escape(t.caption) << "</caption>";
      h << "<tr>";
      for (const auto& c : t.header) h << "<th>" << html_escape(c) << "</th>";
      h << "</tr>\n";
      for (std::size_t r = 0; r < t.rows.size(); ++r) {
        const bool hl = std::find(t.highlight.begin(), t.highlight.end(), r) != t.highlight.end();
        h << (hl ? "<tr class=\"highlight\">" : "<tr>");
        for (const auto& c : t.rows[r]) h << "<td>" << html_escape(c) << "</td>";
        h << "</tr>\n";
      }
      h << "</table>\n";
    }
    for (const auto& f : s.figures) {
      // read from where this run's figure is now (staged until the run's outputs are committed)
      const fs::path svg = current_output_path((fs::path(folder_) / (f.name + ".svg")).string());
      h << "<figure id=\"" << html_escape(f.name) << "\">";
      if (f.rendered && fs::exists(svg))
        h << "<img alt=\"" << html_escape(f.caption.substr(0, 80)) << "\" src=\"data:image/svg+xml;base64,"
          << base64(slurp(svg.string())) << "\">";
      else
        h << "<p class=\"missing\">figure not rendered (gnuplot missing or failed; script "
          << html_escape(f.name) << ".gp)</p>";
      h << "<figcaption>" << html_escape(f.caption) << " <span class=\"files\">[" << html_escape(f.name)
        << ".svg, " << html_escape(f.name) << ".gp, data " << html_escape(f.name) << "*.csv]</span></figcaption></figure>\n";
    }
    h << "</section>\n";
  }
  h << "<script>" << kCheckScript << "</script>\n</body></html>\n";
  const std::string path = (fs::path(folder_) / "index.html").string();
  write_file_atomically(path, h.str());
  return path;
}

}  // namespace vehs::tools
