#include "tools/study_output.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace vehs::tools {

nlohmann::ordered_json study_to_json(const identify::StudyResult& study) {
  const auto& points = study.points;
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  nlohmann::ordered_json j;
  j["coverage_95"] = study.coverage;
  j["intervals"] = study.intervals;
  j["points"] = nlohmann::ordered_json::array();
  for (const auto& p : points) {
    nlohmann::ordered_json pj;
    pj["dt"] = p.point.dt;
    pj["samples"] = p.point.samples;
    pj["support_exact_fraction"] = p.support_exact;
    pj["estimators_used"] = p.estimators_used;
    pj["seconds_simulate"] = p.seconds_simulate;
    pj["seconds_identify"] = p.seconds_identify;
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& s : p.parameters)
      params[s.name] = {{"truth", s.truth}, {"mean", s.mean}, {"sd", s.sd},
                        {"mean_stderr", num(s.mean_stderr)}, {"coverage_95", s.coverage}};
    pj["parameters"] = params;
    j["points"].push_back(pj);
  }
  return j;
}

Table study_table(const identify::StudyResult& study) {
  const auto& points = study.points;
  Table t({"dt", "samples", "truth", "mean", "sd", "mean_stderr", "coverage_95", "support_exact"},
          "parameter");
  for (const auto& p : points)
    for (const auto& s : p.parameters)
      t.add_row(s.name, {p.point.dt, static_cast<double>(p.point.samples), s.truth, s.mean, s.sd,
                         s.mean_stderr, s.coverage, p.support_exact});
  return t;
}

std::string study_text(const identify::StudyResult& study) {
  const auto& points = study.points;
  auto g = [](double v, int digits) {
    std::ostringstream os;
    os.precision(digits);
    os << v;
    return os.str();
  };
  std::ostringstream os;
  os << std::left << std::setw(12) << "parameter" << std::right << std::setw(10) << "truth";
  for (const auto& p : points)
    os << std::setw(26) << ("dt=" + g(p.point.dt, 4) + ", N=" + std::to_string(p.point.samples));
  os << "\n";
  if (points.empty()) return os.str();
  for (std::size_t i = 0; i < points.front().parameters.size(); ++i) {
    const auto& first = points.front().parameters[i];
    os << std::left << std::setw(12) << first.name << std::right << std::setw(10) << g(first.truth, 5);
    for (const auto& p : points) {
      const auto& s = p.parameters[i];
      os << std::setw(26) << (g(s.mean, 5) + " (" + g(s.sd, 2) + ")");
    }
    os << "\n";
  }
  os << std::left << std::setw(22) << "exact support" << std::right;
  for (const auto& p : points) os << std::setw(26) << (g(100.0 * p.support_exact, 3) + " %");
  os << "\n";
  os << "coverage of the nominal 95 % intervals: " << g(100.0 * study.coverage, 3) << " % of " << study.intervals
     << " (repeat, parameter) pairs\n";
  return os.str();
}

}  // namespace vehs::tools
