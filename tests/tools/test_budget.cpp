// Budgets estimated before work (src/tools/budget.hpp): refused above the documented limits with
// one line, lifted by "force": true.
#include <catch2/catch.hpp>

#include <string>

#include "tools/budget.hpp"
#include "vehs/core/error.hpp"

using namespace vehs::tools;

TEST_CASE("a budget above its limit is refused with the estimate - unless forced", "[budget][errors]") {
  const Config plain(nlohmann::json::object(), "sim.json");
  const std::vector<Estimate> steps = {
      {Resource::Steps, 2e12, "integration steps (2 records)", "use fewer trajectories"}};
  std::string e;
  try {
    check_budget(plain, steps);
  } catch (const vehs::Error& err) {
    e = err.what();
  }
  CHECK(e == "sim.json: the run needs about 2e+12 integration steps (2 records) (limit 1e+11): use fewer "
             "trajectories, or set \"force\": true (--force) to run it anyway");
  CHECK_NOTHROW(check_budget(Config({{"force", true}}, "sim.json"), steps));
  CHECK_NOTHROW(check_budget(plain, {{Resource::Steps, 1e11, "", ""}}));  // at the limit
  CHECK_THROWS_WITH(check_budget(plain, {{Resource::Output, 3e10, "(CSV)", "write less"}}),
                    Catch::Contains("about 30 GB of output files (CSV) (limit 20 GB)"));
  CHECK_THROWS_WITH(check_budget(plain, {{Resource::Memory, 1e20, "", "less"}}),
                    Catch::Contains("GB of memory (limit"));
  CHECK_THROWS_WITH(check_budget(plain, {{Resource::CellSolves, 1.6e11, "cell solves", "fewer"}}),
                    Catch::Contains("1.6e+11 cell solves (limit 1e+10)"));
  CHECK_THROWS_WITH(check_budget(Config({{"force", 1}}, "sim.json"), steps), Catch::Contains("'force' must be true or false"));
}
