#include "positive_diffusion.hpp"

#include <algorithm>
#include <string>

#include "vehs/core/diffusion_domain.hpp"
#include "vehs/core/terms.hpp"

namespace vehs::identify::detail {

StateBox state_box(const Dataset& data, double v_sd) {
  StateBox b;
  b.x_lo = b.x_hi = data.x[0];
  for (double v : data.x) b.x_lo = std::min(b.x_lo, v), b.x_hi = std::max(b.x_hi, v);
  b.y_sd = v_sd;
  return b;
}

bool positive_on(const Dictionary& psi, const Eigen::VectorXd& q, const StateBox& box) {
  TermList a22;
  bool on_y = false;
  for (int j = 0; j < psi.size(); ++j)
    if (q[j] != 0.0) a22.push_back({psi.term(j), q[j]}), on_y = on_y || psi.term(j).depends_on_y();
  if (box.x_lo <= 0.0 && box.x_hi >= 0.0 && !(evaluate(a22, 0.0, 0.0) > 0.0)) return false;
  Model model;
  model.diffusion = a22;
  if (!diffusion_negative_at_large_x(model).empty()) return false;
  const int nx = 201, ny = on_y ? 41 : 1;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double x = box.x_lo + (box.x_hi - box.x_lo) * i / (nx - 1);
      const double y = on_y ? 4.0 * box.y_sd * (2.0 * j / (ny - 1) - 1.0) : 0.0;
      if (!(evaluate(a22, x, y) > 0.0)) return false;
    }
  return true;
}

void positive_step(SelectionResult& sel, const QuadraticStats& total, const Dictionary& psi,
                   const std::vector<bool>& keep, const StateBox& box) {
  const int K = psi.size();
  auto positive = [&](const SupportFit& f) { return positive_on(psi, full_coefficients(f, K), box); };
  if (positive(sel.path[static_cast<std::size_t>(sel.chosen)])) return;
  for (int step = sel.chosen + 1; step < static_cast<int>(sel.path.size()); ++step)
    if (positive(sel.path[static_cast<std::size_t>(step)])) {
      sel.rule += "; a22 <= 0 inside the data at that step: the first sparser step with a22 > 0 there (step " +
                  std::to_string(step) + ")";
      sel.chosen = step;
      return;
    }
  // the path dropped the constant on its way: the constant diffusion (and the kept terms)
  std::vector<int> constant;
  for (int j = 0; j < K; ++j)
    if (psi.term(j) == Term::monomial(0) || keep[static_cast<std::size_t>(j)]) constant.push_back(j);
  if (constant.empty()) return;  // none: identify-vehs refuses the model
  const SupportFit f = fit_support(total, constant);
  if (!positive(f)) return;
  sel.path.push_back(f);
  sel.chosen = static_cast<int>(sel.path.size()) - 1;
  sel.rule += "; a22 <= 0 inside the data at that step and every sparser one: the constant diffusion";
}

}  // namespace vehs::identify::detail
