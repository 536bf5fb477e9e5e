// The units of a diagnosis's paired tests.
#include <algorithm>
#include <limits>

#include "comparison.hpp"
#include "vehs/core/error.hpp"

namespace vehs::diagnose::detail {

UnitPlan plan_units(const Dataset& data, const Lens& lens, int min_units, Result& res) {
  UnitPlan plan;
  const std::size_t nrec = data.records.size();
  const std::size_t per = nrec >= static_cast<std::size_t>(min_units)
                              ? 1
                              : (static_cast<std::size_t>(min_units) + nrec - 1) / nrec;
  std::vector<UnitSpan>& units = plan.units;
  std::size_t rows_total = 0, min_unit_len = std::numeric_limits<std::size_t>::max(), min_unit_rows = min_unit_len;
  for (std::size_t r = 0; r < nrec; ++r) {
    const std::size_t n = data.records[r].size;
    const std::size_t nrows = lens.rows(n);
    rows_total += nrows;
    std::size_t blocks = per;
    while (blocks > 1 && n / blocks < 256) --blocks;
    for (std::size_t b = 0; b < blocks; ++b) {
      UnitSpan un{r, n * b / blocks, n * (b + 1) / blocks};
      units.push_back(un);
      min_unit_len = std::min(min_unit_len, un.end - un.begin);
      const std::size_t ub = std::max(un.begin, lens.lead()), ue = std::min(un.end, n - std::min(n, lens.trail()));
      min_unit_rows = std::min(min_unit_rows, ue > ub ? ue - ub : 0);
    }
  }
  res.rows = rows_total;
  res.units = units.size();
  res.unit_kind = per == 1 ? "records" : "time blocks (" + std::to_string(per) + " per record)";
  if (rows_total < 2000)
    throw Error("too little data: " + std::to_string(rows_total) + " usable rows in " + std::to_string(nrec) +
                " records (at least 2000 needed for the one-step statistics)");
  if (min_unit_rows < 32)
    throw Error("a record is too short: a unit of only " + std::to_string(min_unit_rows) +
                " usable rows (records need at least 32 rows beyond the lens's stencil)");
  const int U = static_cast<int>(units.size());
  if (U < 8)
    res.warnings.push_back("only " + std::to_string(U) + " units: the tests have little power and their calibration rests on few degrees of freedom");
  if (per > 1)
    res.warnings.push_back("fewer records than min_units: records are cut into time blocks treated as "
                           "independent units, which assumes blocks longer than the correlation time");
  plan.per = per;
  plan.rows = rows_total;
  plan.min_unit_len = min_unit_len;
  plan.min_unit_rows = min_unit_rows;
  return plan;
}

}  // namespace vehs::diagnose::detail
