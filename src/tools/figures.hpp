#pragma once
// gnuplot figures written next to their data so that users can restyle them.
#include <string>
#include <string_view>

namespace vehs::tools {

/// Writes `<dir>/<name>.gp` (the terminal/output lines followed by `body`) and runs gnuplot in
/// `dir` to produce `<dir>/<name>.<format>` (format "svg" or "png"). The script refers to its
/// data files by names relative to `dir`. Returns the figure's path, or an empty string (with a
/// warning on stderr) when gnuplot is missing or fails; the script is kept either way.
std::string render_figure(const std::string& dir, const std::string& name, const std::string& body,
                          const std::string& format = "svg", int width = 800, int height = 560);

/// `text` as a gnuplot single-quoted string literal: every ' doubled, control characters (a newline
/// would start a new command) as spaces. Inside single quotes gnuplot expands neither backquotes nor
/// macros, so a unit, label or file name written this way can never run a command. Every text a
/// figure script takes from a config, model or data file goes through it.
std::string gnuplot_quote(std::string_view text);

/// True when a gnuplot executable is on the PATH.
bool gnuplot_available();

}  // namespace vehs::tools
