#pragma once
// A self-contained HTML report: every figure is an SVG rendered by gnuplot, embedded in the page
// as a data URI (the page works when moved alone), while the SVG, its data CSV and its gnuplot
// script stay beside the page so users can restyle them.
#include <deque>
#include <string>
#include <vector>

#include "tools/table.hpp"

namespace vehs::tools {

struct ReportFigure {
  std::string name;     ///< file stem in the report folder: <name>.svg, <name>.gp, <name>*.csv
  std::string caption;  ///< what the figure shows and how to read it
  bool rendered = false;
};

struct ReportTable {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// Row indices to highlight (e.g. failed checks).
  std::vector<std::size_t> highlight;
};

struct ReportLink {
  std::string text, href;  ///< href relative to the page
};

struct ReportSection {
  std::string title;
  std::vector<std::string> paragraphs;  ///< plain text (escaped on output)
  std::vector<ReportLink> links;        ///< a list of links after the paragraphs
  std::vector<ReportTable> tables;
  std::vector<ReportFigure> figures;
  std::string id;                  ///< the section element's id (e.g. "top-card"); none when empty
  bool card = false;               ///< drawn as a framed card (the page's summary)
  std::vector<std::string> code;   ///< copy-paste commands, one block each, after the paragraphs
};

class Report {
 public:
  Report(std::string folder, std::string title) : folder_(std::move(folder)), title_(std::move(title)) {}

  const std::string& folder() const { return folder_; }
  /// The section of that title, added at the end when new; the reference stays valid while the
  /// report lives (further sections do not move it).
  ReportSection& section(const std::string& title);

  /// Writes <name>.csv (from `data`) and renders <name>.svg from the gnuplot `body` (which
  /// plots '<name>.csv' or other CSVs written beforehand) into the report folder; adds the figure
  /// to `section`. A failed rendering is reported in the page instead of the image.
  void add_figure(ReportSection& section, const std::string& name, const std::string& caption,
                  const Table& data, const std::string& gnuplot_body);
  /// Same, for a figure whose data files were already written into the folder.
  void add_figure(ReportSection& section, const std::string& name, const std::string& caption,
                  const std::string& gnuplot_body);

  /// Writes <folder>/index.html atomically; returns its path.
  std::string write_html() const;
  std::size_t figure_count() const;

 private:
  std::string folder_, title_;
  std::deque<ReportSection> sections_;  ///< (a vector moved them: a held reference dangled)
};

/// HTML-escapes text.
std::string html_escape(const std::string& text);

}  // namespace vehs::tools
