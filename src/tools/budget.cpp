#include "tools/budget.hpp"

#include "vehs/core/detail/format.hpp"
#include "vehs/core/detail/memory.hpp"
#include "vehs/core/error.hpp"

namespace vehs::tools {

namespace {

std::string amount_text(Resource r, double amount) {
  if (r == Resource::Memory || r == Resource::Output)
    return vehs::detail::format_number(amount / 1e9, 3) + " GB";
  return vehs::detail::format_number(amount, 3);
}

std::string resource_name(Resource r) {
  switch (r) {
    case Resource::Steps: return "";
    case Resource::CellSolves: return "";
    case Resource::Memory: return " of memory";
    case Resource::Output: return " of output files";
  }
  return "";
}

}  // namespace

double budget_limit(Resource resource) {
  switch (resource) {
    case Resource::Steps: return kMaxSteps;
    case Resource::CellSolves: return kMaxCellSolves;
    case Resource::Memory: return kMaxMemoryFraction * vehs::detail::physical_memory_bytes();
    case Resource::Output: return kMaxOutputBytes;
  }
  return 0.0;
}

KeySpec force_key() {
  return {"force", "bool",
          "Run even when the budget estimated from the config is above its limit: 1e11 integration "
          "steps, 1e10 FPK cell solves, 3/4 of physical memory, 20 GB of output files (docs/config.md, "
          "Budgets). Also the flag --force.",
          "false"};
}

bool forced(const Config& c) { return c.boolean_or("force", false); }

void check_budget(const Config& c, const std::vector<Estimate>& estimates) {
  if (forced(c)) return;
  for (const auto& e : estimates) {
    const double limit = budget_limit(e.resource);
    if (!(e.amount > limit)) continue;  // (a NaN estimate is no estimate)
    throw Error(c.file() + ": the run needs about " + amount_text(e.resource, e.amount) + resource_name(e.resource) +
                (e.what.empty() ? "" : " " + e.what) + " (limit " + amount_text(e.resource, limit) + "): " + e.lower +
                ", or set \"force\": true (--force) to run it anyway");
  }
}

}  // namespace vehs::tools
