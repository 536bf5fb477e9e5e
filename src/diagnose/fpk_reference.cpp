// The stationary FPK density of the model as the reference of a diagnosis's p(x), E[X²] and
// E[Y²] (models with a stationary 2-D FPK only).
#include <cmath>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/core/error.hpp"

namespace vehs::diagnose::detail {

void add_fpk_reference(const Comparison& cmp, Result& res) {
  const Options& opt = cmp.options;
  const fpk::FpkModel* fm_ptr = cmp.fpk.get();
  if (opt.fpk && fm_ptr) {
    try {
      fpk::GridRequest req;
      req.grid.x.n = opt.fpk_cells;
      req.grid.y.n = opt.fpk_cells;
      const fpk::StationaryResult st =
          fpk::solve_with_domain(*fm_ptr, req, fpk::SolveOptions{});
      const auto& g = st.grid;
      for (double xq : res.px.at) {
        const double fi = (xq - g.x.min) / g.x.h() - 0.5;
        const int i = static_cast<int>(std::floor(fi));
        double v = 0.0;
        if (i >= 0 && i + 1 < g.x.n) {
          const double t = fi - i;
          v = (1 - t) * st.marginal_x[static_cast<std::size_t>(i)] + t * st.marginal_x[static_cast<std::size_t>(i) + 1];
        }
        res.px.reference.push_back(v);
      }
      res.quantities[0].reference = st.moments.exx;
      res.quantities[1].reference = st.moments.eyy;
      res.fpk_note = "stationary FPK of the model on " + std::to_string(g.x.n) + " x " + std::to_string(g.y.n) +
                     " cells" +
                     (st.refinements > 0 ? " (refined from " + std::to_string(opt.fpk_cells) +
                                               " per axis, which did not resolve the model)"
                                         : std::string()) +
                     " over x in [" + fmt(g.x.min) + ", " + fmt(g.x.max) + "], y in [" + fmt(g.y.min) + ", " +
                     fmt(g.y.max) + "]";
    } catch (const Error& e) {
      res.fpk_note = std::string("the stationary FPK of the model could not be solved: ") + e.what();
      res.warnings.push_back("no FPK reference: " + res.fpk_note);  // never dropped silently
    }
  } else if (!opt.fpk) {
    res.fpk_note = "FPK reference switched off";
  }
}

}  // namespace vehs::diagnose::detail
