#include "tools/statistics_file.hpp"

#include "tools/table.hpp"
#include "vehs/io/atomic_file.hpp"

namespace vehs::tools {

nlohmann::ordered_json statistics_to_json(const sim::MonteCarloStatistics& st) {
  nlohmann::ordered_json j;
  for (const auto& [k, e] : st.moments) j[k] = e.value;
  j["stderr"] = nlohmann::ordered_json::object();
  for (const auto& [k, e] : st.moments) j["stderr"][k] = e.stderr_;
  j["records"] = st.records;
  j["samples_per_record"] = st.samples_per_record;
  j["discard"] = st.discard;
  j["error_method"] = st.error_method;
  if (st.has_histograms) {
    const auto& px = st.px;
    const auto& py = st.py;
    const auto& pxy = st.pxy;
    nlohmann::ordered_json hj;
    hj["x"] = {px.lo, px.hi, px.counts.size()};
    hj["y"] = {py.lo, py.hi, py.counts.size()};
    hj["grid"] = "cell-centred: n cells over [min, max], centre of cell i at min + (i + 1/2)(max - min)/n";
    hj["outside_fraction_x"] = px.total > 0 ? px.outside / px.total : 0.0;
    hj["outside_fraction_y"] = py.total > 0 ? py.outside / py.total : 0.0;
    hj["outside_fraction_xy"] = pxy.total > 0 ? pxy.outside / pxy.total : 0.0;
    j["histograms"] = hj;
  }
  return j;
}

void write_statistics(const sim::MonteCarloStatistics& st, const std::string& json_path,
                      const std::string& px_csv, const std::string& py_csv, const std::string& pxy_csv,
                      const nlohmann::ordered_json& extra) {
  nlohmann::ordered_json j = statistics_to_json(st);
  const auto& px = st.px;
  const auto& py = st.py;
  const auto& pxy = st.pxy;
  for (auto it = extra.begin(); it != extra.end(); ++it) j[it.key()] = it.value();
  auto relative = [&](const std::string& p) {
    // name the CSV relative to the JSON's folder when they share it
    const auto slash = json_path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "" : json_path.substr(0, slash + 1);
    return !dir.empty() && p.compare(0, dir.size(), dir) == 0 ? p.substr(dir.size()) : p;
  };
  if (st.has_histograms) {
    if (!px_csv.empty()) {
      Table t({"x", "p"});
      const auto d = px.density();
      for (std::size_t i = 0; i < d.size(); ++i) t.add_row({px.center(i), d[i]});
      t.write_csv(px_csv);
      j["histograms"]["p(x)"] = relative(px_csv);
    }
    if (!py_csv.empty()) {
      Table t({"y", "p"});
      const auto d = py.density();
      for (std::size_t i = 0; i < d.size(); ++i) t.add_row({py.center(i), d[i]});
      t.write_csv(py_csv);
      j["histograms"]["p(y)"] = relative(py_csv);
    }
    if (!pxy_csv.empty()) {
      Table t({"x", "y", "p"});
      const auto d = pxy.density();
      const double hx = (pxy.xhi - pxy.xlo) / static_cast<double>(pxy.nx);
      const double hy = (pxy.yhi - pxy.ylo) / static_cast<double>(pxy.ny);
      for (std::size_t i = 0; i < pxy.nx; ++i)
        for (std::size_t k = 0; k < pxy.ny; ++k)
          t.add_row({pxy.xlo + (static_cast<double>(i) + 0.5) * hx,
                     pxy.ylo + (static_cast<double>(k) + 0.5) * hy, d[i * pxy.ny + k]});
      t.write_csv(pxy_csv);
      j["histograms"]["p(x,y)"] = relative(pxy_csv);
    }
  }
  if (!json_path.empty()) write_json_atomically(json_path, j);
}

}  // namespace vehs::tools
