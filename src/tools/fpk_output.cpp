#include "tools/fpk_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "tools/figures.hpp"
#include "tools/measurement_config.hpp"
#include "tools/table.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"

namespace vehs::tools {

using namespace vehs::fpk;

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

nlohmann::ordered_json axis_json(const Axis& a) { return nlohmann::ordered_json::array({a.min, a.max, a.n}); }

}  // namespace

void write_density(const std::string& path, const StationaryResult& r) {
  const Grid& g = r.grid;
  if (ends_with(path, ".npy")) {
    std::ostringstream header;
    header << "{'descr': '<f8', 'fortran_order': False, 'shape': (" << g.x.n << ", " << g.y.n << "), }";
    std::string h = header.str();
    const std::size_t total = 10 + h.size() + 1;
    h.append((64 - total % 64) % 64, ' ');
    h.push_back('\n');
    write_file_atomically(path, [&](std::ostream& os) {
      os.write("\x93NUMPY\x01\x00", 8);
      const auto len = static_cast<std::uint16_t>(h.size());
      const char le[2] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
      os.write(le, 2);
      os.write(h.data(), static_cast<std::streamsize>(h.size()));
      os.write(reinterpret_cast<const char*>(r.density.data()),
               static_cast<std::streamsize>(r.density.size() * sizeof(double)));
    });
    return;
  }
  write_file_atomically(path, [&](std::ostream& os) {
    os << "x,y,p\n" << std::setprecision(12);
    for (int i = 0; i < g.x.n; ++i)
      for (int j = 0; j < g.y.n; ++j)
        os << g.x.center(i) << ',' << g.y.center(j) << ',' << r.density[g.index(i, j)] << '\n';
  });
}

void write_marginals(const std::string& x_path, const std::string& y_path, const FpkModel& model,
                     const StationaryResult& r) {
  Table tx({"x", "p", "U"});
  for (int i = 0; i < r.grid.x.n; ++i) {
    const double x = r.grid.x.center(i);
    tx.add_row({x, r.marginal_x[static_cast<std::size_t>(i)], model.potential(x)});
  }
  tx.write_csv(x_path, 12);
  Table ty({"y", "p"});
  for (int j = 0; j < r.grid.y.n; ++j)
    ty.add_row({r.grid.y.center(j), r.marginal_y[static_cast<std::size_t>(j)]});
  ty.write_csv(y_path, 12);
}

nlohmann::ordered_json result_to_json(const StationaryResult& r) {
  nlohmann::ordered_json j;
  const Moments& m = r.moments;
  j["E[X^2]"] = m.exx;
  j["E[Y^2]"] = m.eyy;
  j["E[XY]"] = m.exy;
  j["E[X]"] = m.ex;
  j["E[Y]"] = m.ey;
  j["boundary_mass"] = r.boundary_mass;
  j["grid"] = {{"x", axis_json(r.grid.x)},
               {"y", axis_json(r.grid.y)},
               {"automatic", r.auto_domain},
               {"enlargements", r.domain_enlargements},
               {"refinements", r.refinements}};
  auto wells = nlohmann::ordered_json::array();
  for (const auto& w : r.wells)
    wells.push_back({{"x_min", w.x_min}, {"U", w.potential}, {"range", {w.lo, w.hi}}, {"mass", w.mass}});
  j["wells"] = wells;
  j["identities"] = {
      {"note", "exact stationary identities evaluated on the discrete density; each should be 0 up to "
               "the discretisation error"},
      {"E[XY]/sqrt(E[X^2]E[Y^2])", r.identities.xy},
      {"virial (E[Y^2] + E[X b2]) / E[Y^2]", r.identities.virial},
      {"energy (E[Y b2] + E[a22]/2) / (E[a22]/2)", r.identities.energy}};
  const SolveSummary& s = r.summary;
  j["solve"] = {{"solver", s.solver},
                {"scheme", s.scheme},
                {"assemble_seconds", s.assemble_seconds},
                {"solve_seconds", s.solve_seconds},
                {"iterations", s.iterations},
                {"converged", s.converged},
                {"residual", s.residual},
                {"dropped_equation_residual", s.dropped_equation_residual},
                {"negative_mass", s.negative_mass},
                {"min_density_over_max", s.min_density_ratio},
                {"matrix_nonzeros", s.nonzeros},
                {"factor_nonzeros", s.factor_nonzeros},
                {"factor_megabytes", s.factor_megabytes},
                {"normalization_attempts", s.normalization_attempts}};
  return j;
}

void write_sweep_table(const std::string& path, const SweepResult& sw) {
  std::size_t max_wells = 0;
  for (const auto& p : sw.points) max_wells = std::max(max_wells, p.wells.size());
  std::vector<std::string> cols;
  for (const auto& a : sw.axes) cols.push_back(a.name);
  for (const char* c : {"E[X^2]", "E[Y^2]", "E[XY]", "boundary_mass", "residual"}) cols.push_back(c);
  for (std::size_t w = 0; w < max_wells; ++w) cols.push_back("well_" + std::to_string(w + 1));
  cols.push_back("ok");
  Table t(cols);
  const double nan = std::nan("");
  for (const auto& p : sw.points) {
    std::vector<double> row = p.parameters;
    const bool ok = p.error.empty();
    for (double v : {p.moments.exx, p.moments.eyy, p.moments.exy, p.boundary_mass, p.residual})
      row.push_back(ok ? v : nan);
    for (std::size_t w = 0; w < max_wells; ++w) row.push_back(ok && w < p.wells.size() ? p.wells[w].mass : nan);
    row.push_back(ok ? 1.0 : 0.0);
    t.add_row(row);
  }
  t.write_csv(path, 10);
}

nlohmann::ordered_json sweep_to_json(const SweepResult& sw) {
  nlohmann::ordered_json j;
  auto axes = nlohmann::ordered_json::array();
  for (const auto& a : sw.axes) axes.push_back({{"name", a.name}, {"values", a.values}});
  j["parameters"] = axes;
  j["grid"] = {{"x", axis_json(sw.grid.x)}, {"y", axis_json(sw.grid.y)}};
  j["seconds"] = sw.seconds;
  j["threads"] = sw.threads;
  auto pts = nlohmann::ordered_json::array();
  std::size_t failed = 0;
  for (const auto& p : sw.points) {
    nlohmann::ordered_json o;
    for (std::size_t a = 0; a < sw.axes.size(); ++a) o[sw.axes[a].name] = p.parameters[a];
    if (p.error.empty()) {
      o["E[X^2]"] = p.moments.exx;
      o["E[Y^2]"] = p.moments.eyy;
      o["E[XY]"] = p.moments.exy;
      o["boundary_mass"] = p.boundary_mass;
      if (p.own_domain) o["grid"] = "own automatic domain (the shared grid did not resolve this point)";
      auto wm = nlohmann::ordered_json::array();
      for (const auto& w : p.wells) wm.push_back({{"x_min", w.x_min}, {"mass", w.mass}});
      o["wells"] = wm;
    } else {
      o["error"] = p.error;
      ++failed;
    }
    pts.push_back(o);
  }
  j["failed_points"] = failed;
  j["points"] = pts;
  return j;
}

// ---- figures --------------------------------------------------------------------------------

std::vector<std::string> density_figures(const std::string& dir, const FpkModel& model,
                                         const StationaryResult& r, const nlohmann::json& units) {
  std::vector<std::string> out;
  const Grid& g = r.grid;
  const std::string xl = with_unit("x", "x", units), yl = with_unit("y", "v", units);
  // the region where the density exceeds 1e-4 of its peak, padded by 5 %
  double peak = 0.0;
  for (double p : r.density) peak = std::max(peak, p);
  int ilo = g.x.n, ihi = -1, jlo = g.y.n, jhi = -1;
  for (int i = 0; i < g.x.n; ++i)
    for (int j = 0; j < g.y.n; ++j)
      if (r.density[g.index(i, j)] > 1e-4 * peak) ilo = std::min(ilo, i), ihi = std::max(ihi, i), jlo = std::min(jlo, j), jhi = std::max(jhi, j);
  double x0 = g.x.min, x1 = g.x.max, y0 = g.y.min, y1 = g.y.max;
  if (ihi >= ilo && jhi >= jlo) {
    const double px = 0.05 * (g.x.center(ihi) - g.x.center(ilo)), py = 0.05 * (g.y.center(jhi) - g.y.center(jlo));
    x0 = std::max(g.x.min, g.x.center(ilo) - px), x1 = std::min(g.x.max, g.x.center(ihi) + px);
    y0 = std::max(g.y.min, g.y.center(jlo) - py), y1 = std::min(g.y.max, g.y.center(jhi) + py);
  }
  // Heat map data: block averages down to at most 200 × 200 points, one x block per paragraph.
  const int bx = std::max(1, (g.x.n + 199) / 200), by = std::max(1, (g.y.n + 199) / 200);
  write_file_atomically(dir + "/density_map.csv", [&](std::ostream& os) {
    os << "x,y,p\n" << std::setprecision(8);
    for (int i0 = 0; i0 + bx <= g.x.n; i0 += bx) {
      for (int j0 = 0; j0 + by <= g.y.n; j0 += by) {
        double s = 0.0;
        for (int i = i0; i < i0 + bx; ++i)
          for (int j = j0; j < j0 + by; ++j) s += r.density[g.index(i, j)];
        const double xc = 0.5 * (g.x.center(i0) + g.x.center(i0 + bx - 1));
        const double yc = 0.5 * (g.y.center(j0) + g.y.center(j0 + by - 1));
        os << xc << ',' << yc << ',' << s / (bx * by) << '\n';
      }
      os << '\n';
    }
  });
  std::ostringstream heat;
  heat << "set title " << gnuplot_quote("stationary density p(x, y) (" + r.summary.scheme + ", " + std::to_string(g.x.n) + "x" +
                                    std::to_string(g.y.n) + " cells; shown where p > 1e-4 of its peak)")
       << "\nset xlabel " << gnuplot_quote(xl) << "\nset ylabel " << gnuplot_quote(yl) << "\nset view map\nset pm3d map interpolate 0,0\n"
          "set palette rgb 33,13,10\nset cbrange [0:*]\nset xrange [" << x0 << ":" << x1 << "]\nset yrange ["
       << y0 << ":" << y1 << "]\nset key off\n"
          "splot 'density_map.csv' skip 1 using 1:2:3 with pm3d\n";
  if (auto f = render_figure(dir, "density_map", heat.str()); !f.empty()) out.push_back(f);
  // Marginals with the potential and the wells.
  write_marginals(dir + "/marginal_x.csv", dir + "/marginal_y.csv", model, r);
  std::ostringstream mx;
  mx << "set multiplot layout 1,2\nset title 'p(x) and the potential U(x)'\nset xlabel " << gnuplot_quote(xl) << "\nset ylabel "
     << gnuplot_quote(with_unit("p(x)", "1/x", units)) << "\nset y2label " << gnuplot_quote(with_unit("U(x)", "v2", units))
     << "\nset ytics nomirror\nset y2tics\nset key below horizontal\n";
  for (const auto& w : r.wells)
    if (w.lo > g.x.min) mx << "set arrow from " << w.lo << ", graph 0 to " << w.lo << ", graph 1 nohead dt 3 lc rgb 'gray'\n";
  double umin = 1e300;
  for (int i = 0; i < g.x.n; ++i) umin = std::min(umin, model.potential(g.x.center(i)));
  // show the wells: U up to three times the highest interior barrier (the walls are clipped)
  double barrier = umin;
  for (const auto& w : r.wells)
    if (w.lo > g.x.min) barrier = std::max(barrier, model.potential(w.lo));
  const double span = barrier > umin ? 3.0 * (barrier - umin) : 1.0;
  mx << "set y2range [" << umin - 0.05 * span << ":" << umin + span << "]\n";
  mx << "plot 'marginal_x.csv' skip 1 using 1:2 with lines lw 2 title 'p(x)', "
        "'' skip 1 using 1:3 axes x1y2 with lines dt 2 title 'U(x)'\n"
        "unset arrow\nset title 'p(y)'\nset xlabel " << gnuplot_quote(yl) << "\nset ylabel 'p(y)'\nunset y2label\nunset y2tics\n"
        "set ytics mirror\nplot 'marginal_y.csv' skip 1 using 1:2 with lines lw 2 title 'p(y)'\n"
        "unset multiplot\n";
  if (auto f = render_figure(dir, "marginals", mx.str(), "svg", 1100, 480); !f.empty()) out.push_back(f);
  return out;
}

std::vector<std::string> sweep_figures(const std::string& dir, const SweepResult& sw) {
  std::vector<std::string> out;
  if (sw.axes.empty()) return out;
  write_sweep_table(dir + "/sweep.csv", sw);
  const std::size_t np = sw.axes.size();
  // column indices (1-based): parameters, then E[X^2], E[Y^2]
  const std::size_t cx2 = np + 1, cy2 = np + 2;
  if (np == 1) {
    std::ostringstream b;
    b << "set multiplot layout 1,2\nset xlabel " << gnuplot_quote(sw.axes[0].name) << "\nset key off\nset grid\n"
      << "set title 'E[Y^2] (mean power ~ E[Y^2])'\nplot 'sweep.csv' skip 1 using 1:" << cy2
      << " with linespoints pt 7\nset title 'E[X^2]'\nplot 'sweep.csv' skip 1 using 1:" << cx2
      << " with linespoints pt 7\nunset multiplot\n";
    if (auto f = render_figure(dir, "sweep", b.str(), "svg", 1100, 480); !f.empty()) out.push_back(f);
    return out;
  }
  // Two parameters: surfaces like the paper's Fig. 5, from a paragraph-separated copy.
  const std::size_t n2 = sw.axes[1].values.size();
  write_file_atomically(dir + "/sweep_surface.csv", [&](std::ostream& os) {
    os << sw.axes[0].name << ',' << sw.axes[1].name << ",E[X^2],E[Y^2]\n" << std::setprecision(10);
    for (std::size_t k = 0; k < sw.points.size(); ++k) {
      const auto& p = sw.points[k];
      os << p.parameters[0] << ',' << p.parameters[1] << ',';  // a failed point: empty cells (gnuplot: missing)
      if (p.error.empty()) os << p.moments.exx << ',' << p.moments.eyy;
      else os << ',';
      os << '\n';
      if ((k + 1) % n2 == 0) os << '\n';
    }
  });
  for (int which = 0; which < 2; ++which) {
    std::ostringstream b;
    const char* what = which == 0 ? "E[Y^2]" : "E[X^2]";
    b << "set title '" << what << "'\nset xlabel " << gnuplot_quote(sw.axes[0].name) << "\nset ylabel "
      << gnuplot_quote(sw.axes[1].name) << "\nset pm3d\nset palette rgb 33,13,10\nset hidden3d\nset key off\n"
      << "set ticslevel 0\nsplot 'sweep_surface.csv' skip 1 using 1:2:" << (which == 0 ? 4 : 3)
      << " with pm3d\n";
    if (auto f = render_figure(dir, which == 0 ? "sweep_EY2" : "sweep_EX2", b.str()); !f.empty())
      out.push_back(f);
  }
  return out;
}

}  // namespace vehs::tools
